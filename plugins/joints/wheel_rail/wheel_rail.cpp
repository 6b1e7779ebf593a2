// The wheel_rail joint plugin (spatial; book Sec. 8.6, Eqs. 8.49-8.74): a wheel (body j) whose
// tread is a surface of revolution about its axle rolls and slides without friction on a rail
// head (body i, often the ground) that is a profile extruded along a straight track.
//
// Surfaces (profile_curve.hpp gives r(s) and h(y)):
//   wheel, body j axes:  x_w(theta, s) = c + s a + r(s) e(theta),  e = cos(theta) b1 + sin(theta) b2
//            (c the wheel centre, a the unit axle, b1, b2 perpendicular to it, s the lateral
//            coordinate along the axle, theta the angular position on the wheel);
//   rail, body i axes:   x_r(xi, eta) = o + A_m [xi, eta, h(eta)]
//            (the joint frame: o on the head, x along the track, z up, y = z x x across it),
//            unit normal nu = A_m [0, -h', 1] / sqrt(1 + h'^2), pointing out of the head.
// The four surface parameters p = (theta, s, xi, eta) are the book's non-generalized
// coordinates (Eq. 8.50). The book's five equations (8.55 and 8.58) make the points coincide
// and the normals parallel; here they are split into four that fix p for any body state,
//     F1 = n . A_j e_theta = 0,  F2 = n . A_j x_w,s = 0      (the normals are parallel, 8.58)
//     F3 = t_xi . d = 0,         F4 = t_eta . d = 0          (the points coincide along the
//                                                             rail's tangents, 8.55)
// with n = A_i nu, t = A_i x_r,p, d = r_w - r_r (r_w = R_j + A_j x_w, r_r = R_i + A_i x_r),
// solved by Newton inside the joint, and the fifth, the normal gap
//     g = n . d,
// which is the joint's ONE row: its multiplier is the normal contact force, the one multiplier
// per contact that C_s^T lambda = 0 leaves (Eq. 8.72 and the text after it). g is stationary in
// p where F = 0 (dg/dtheta, dg/ds vanish by F1, F2; dg/dxi, dg/deta = nu_p . d - n . t = 0 as
// d is along n and nu is a unit vector), so its Jacobian at fixed p is exact (envelope theorem),
// columns [dR_i | dpi_bar_i | dR_j | dpi_bar_j]:
//     J = [ -n^T | -(x_r x nu)^T | n^T | (x_w x A_j^T n)^T ].
// Along the motion gdot = n . w (w = v_j(x_w) - v_i(x_r), the material velocities of the two
// contact points; the turning of n adds ndot . d = 0), so
//     gamma = -( ndot . w + n . (A_j wj~^2 x_w - A_i wi~^2 x_r + A_j (wj x x_w,p pdot_w)
//                                - A_i (wi x x_r,p pdot_r)) ),   ndot = A_i (wi x nu + nu_eta etadot),
//     pdot = -F_p^-1 F_q v   (from dF/dt = 0; needs the profiles' curvature only: C2 suffices,
//                             where the book's 8.58 at acceleration level needs C3).
// A line contact (a cylinder, gamma = 0, on a flat head: C_s rank deficient, book after
// Eq. 8.74) leaves s where the search starts, under the track's centre line, through the
// least-squares Newton step. A cone on a flat head has no point contact and is refused.
// The wheel must stay over the head, facing it (the contact within both profiles' ranges,
// ProfileCurve::domain; a run stops with a DomainError where it leaves them), and its profile
// must make a point contact (a relative curvature of the two profiles of one sign across the
// contact); one contact per
// joint (a flange making a second contact needs a second joint with a flange profile).
// The row is bilateral; the contact pushes while lambda < 0 (compression_sign): a run warns
// where the wheel would lift off.
// Scene keys: bodies: [rail, wheel]; point, axis (up), x_axis (along the track): the rail frame;
// wheel_centre: [x, y, z] world at t = 0 (default the wheel's mass centre); axle: [x, y, z]
// world at t = 0, the direction of +s (default the rail frame's y axis);
// wheel: {type: cone, radius, cone_angle, width} | {type: spline, points: [[s, r], ...]};
// rail: {type: flat} | {type: arc, radius} | {type: spline, points: [[y, h], ...]}.
#include "profile_curve.hpp"

#include <mbd/sdk/contact_joint.hpp>
#include <mbd/sdk/domain_error.hpp>
#include <mbd/sdk/plugin.hpp>
#include <mbd/sdk/plugin_keys.hpp>
#include <mbd/sdk/spatial_primitives.hpp>
#include <mbd/sdk/rotation.hpp>
#include <mbd/sdk/text.hpp>

#include <Eigen/Dense>

#include <cmath>
#include <memory>
#include <string>

namespace {

using mbd::Mat3;
using mbd::Vec3;
using mbd::wheel_rail::CurveValue;
using mbd::wheel_rail::ProfileCurve;
using Mat4 = Eigen::Matrix4d;
using Vec4 = Eigen::Vector4d;

// The two contact points at surface parameters p = (theta, s, xi, eta), world axes unless
// marked _bar (body axes), with what F, F_p and the rates need.
struct Contact {
    Vec3 x_w_bar, x_theta_bar, x_s_bar;  // wheel point and tangents, body j axes
    Vec3 x_r_bar, t_xi_bar, t_eta_bar;   // rail point and tangents, body i axes
    Vec3 nu_bar, nu_eta_bar;             // rail unit normal and d nu / d eta, body i axes
    Vec3 e_theta_bar, e_bar;             // wheel radial direction and its turn, body j axes
    CurveValue r, h;
    Vec3 n, d;                           // world: normal, r_w - r_r
};

class WheelRail final : public mbd::ContactJoint {
public:
    WheelRail(std::unique_ptr<const ProfileCurve> wheel, std::unique_ptr<const ProfileCurve> rail,
              const mbd::Marker& rail_frame, const Vec3& centre, const Vec3& axle)
        : wheel_(std::move(wheel)), rail_(std::move(rail)), o_(rail_frame.u_bar), A_m_(rail_frame.A_bar),
          c_(centre), a_(axle.normalized()) {
        b1_ = mbd::any_perpendicular(a_).normalized();
        b2_ = a_.cross(b1_);
        length_ = std::max(std::abs(wheel_->at(0.0).f), 1e-3);
    }

    void evaluate(const mbd::BodyStates& b, mbd::ConstraintEval& out) const override {
        clear(out);
        const mbd::SpatialBody& bi = b.spatial(0);
        const mbd::SpatialBody& bj = b.spatial(1);
        const Search found = solve(bi, bj);
        const Vec4& p = found.p;
        const Contact k = at(p, bi, bj);
        require_over_the_head(found, k, bi);
        const Vec4 pdot = -decompose(jacobian(k, bi, bj)).solve(rate_at_fixed_p(k, bi, bj));
        const Vec3& wi = bi.omega_bar;
        const Vec3& wj = bj.omega_bar;
        const Vec3 w = bj.point_velocity(k.x_w_bar) - bi.point_velocity(k.x_r_bar);
        const Vec3 ndot = bi.A * (wi.cross(k.nu_bar) + k.nu_eta_bar * pdot[3]);
        const Vec3 wheel_rate = k.x_theta_bar * pdot[0] + k.x_s_bar * pdot[1];
        const Vec3 rail_rate = k.t_xi_bar * pdot[2] + k.t_eta_bar * pdot[3];
        out.C[0] = k.n.dot(k.d);
        out.J.block<1, 3>(0, 0) = -k.n.transpose();
        out.J.block<1, 3>(0, 3) = -k.x_r_bar.cross(k.nu_bar).transpose();
        out.J.block<1, 3>(0, 6) = k.n.transpose();
        out.J.block<1, 3>(0, 9) = k.x_w_bar.cross(bj.A.transpose() * k.n).transpose();
        out.gamma[0] = -(ndot.dot(w) + k.n.dot(bj.A * wj.cross(wj.cross(k.x_w_bar)) -
                                               bi.A * wi.cross(wi.cross(k.x_r_bar)) + bj.A * wj.cross(wheel_rate) -
                                               bi.A * wi.cross(rail_rate)));
    }

private:
    // The surface parameters the search ends at and its merit there (0 at an exact contact).
    struct Search {
        Vec4 p;
        double merit = 0.0;
    };

    // The contact must solve F = 0 with both points on their profiles' ranges: a wheel that
    // has left the rail head has no such point (the search ends with a residual, or the point
    // it finds lies off the head or off the tread). The core names the joint and the time.
    void require_over_the_head(const Search& found, const Contact& k, const mbd::SpatialBody& bi) const {
        const ProfileCurve::Range head = rail_->domain(), tread = wheel_->domain();
        const double eta = found.p[3], s = found.p[1];
        const auto range = [](const ProfileCurve::Range& r, const char* name) {
            return std::string(" (") + name + " from " + mbd::format_number(r.lo) + " to " + mbd::format_number(r.hi) +
                   " m)";
        };
        const std::string advice = "; the wheel must stay over the rail head, facing it (docs/scene-format.md, wheel_rail)";
        // F1, F2 are cosines, F3, F4 lengths over the wheel's radius: 1e-8 is far above
        // round-off and far below any real miss
        if (!(std::sqrt(found.merit) <= 1e-8)) {
            // where the wheel's point closest to the head lies across the head
            const Vec3 local = A_m_.transpose() * (bi.A.transpose() * (k.d + bi.point(k.x_r_bar) - bi.R) - o_);
            std::string where = "the wheel's point nearest the head is at y = " + mbd::format_number(local.y()) +
                                " m across it, " + mbd::format_number(local.z()) + " m above its reference line";
            if (!head.contains(local.y()))
                where += ", " + mbd::format_number(head.outside_by(local.y())) + " m outside the head's profile" +
                         range(head, "y");
            throw mbd::DomainError("no contact point between the wheel and the rail head (the contact search ends "
                                   "with a residual of " + mbd::format_number(std::sqrt(found.merit), 3) + "); " +
                                   where + advice);
        }
        if (!head.contains(eta))
            throw mbd::DomainError("the contact point is at y = " + mbd::format_number(eta) + " m across the rail head, " +
                                   mbd::format_number(head.outside_by(eta)) + " m outside the head's profile" +
                                   range(head, "y") + advice);
        if (!tread.contains(s))
            throw mbd::DomainError("the contact point is at s = " + mbd::format_number(s) + " m along the axle, " +
                                   mbd::format_number(tread.outside_by(s)) + " m outside the wheel's profile" +
                                   range(tread, "s") + advice);
    }

    Contact at(const Vec4& p, const mbd::SpatialBody& bi, const mbd::SpatialBody& bj) const {
        Contact k;
        const double theta = p[0], s = p[1], xi = p[2], eta = p[3];
        k.e_bar = std::cos(theta) * b1_ + std::sin(theta) * b2_;
        k.e_theta_bar = -std::sin(theta) * b1_ + std::cos(theta) * b2_;
        k.r = wheel_->at(s);
        k.x_w_bar = c_ + s * a_ + k.r.f * k.e_bar;
        k.x_theta_bar = k.r.f * k.e_theta_bar;
        k.x_s_bar = a_ + k.r.f1 * k.e_bar;
        k.h = rail_->at(eta);
        k.x_r_bar = o_ + A_m_ * Vec3(xi, eta, k.h.f);
        k.t_xi_bar = A_m_.col(0);
        k.t_eta_bar = A_m_ * Vec3(0.0, 1.0, k.h.f1);
        const double q = std::sqrt(1.0 + k.h.f1 * k.h.f1);
        k.nu_bar = A_m_ * Vec3(0.0, -k.h.f1, 1.0) / q;
        // d nu = (dN - (nu . dN) nu) / |N|, N = A_m [0, -h', 1], dN/deta = A_m [0, -h'', 0]
        const Vec3 N_eta = A_m_ * Vec3(0.0, -k.h.f2, 0.0);
        k.nu_eta_bar = (N_eta - k.nu_bar.dot(N_eta) * k.nu_bar) / q;
        k.n = bi.A * k.nu_bar;
        k.d = bj.point(k.x_w_bar) - bi.point(k.x_r_bar);
        return k;
    }

    Vec4 residual(const Contact& k, const mbd::SpatialBody& bi, const mbd::SpatialBody& bj) const {
        return Vec4(k.n.dot(bj.A * k.e_theta_bar), k.n.dot(bj.A * k.x_s_bar), (bi.A * k.t_xi_bar).dot(k.d),
                    (bi.A * k.t_eta_bar).dot(k.d));
    }

    // F_p, columns (theta, s, xi, eta)
    Mat4 jacobian(const Contact& k, const mbd::SpatialBody& bi, const mbd::SpatialBody& bj) const {
        const Vec3 n_eta = bi.A * k.nu_eta_bar, t_xi = bi.A * k.t_xi_bar, t_eta = bi.A * k.t_eta_bar;
        const Vec3 e = bj.A * k.e_bar, e_theta = bj.A * k.e_theta_bar;
        const Vec3 x_theta = bj.A * k.x_theta_bar, x_s = bj.A * k.x_s_bar;
        const Vec3 t_eta_eta = bi.A * (A_m_ * Vec3(0.0, 0.0, k.h.f2));
        Mat4 Fp;
        Fp << -k.n.dot(e), 0.0, 0.0, n_eta.dot(e_theta),                                   //
            k.r.f1 * k.n.dot(e_theta), k.r.f2 * k.n.dot(e), 0.0, n_eta.dot(x_s),            //
            t_xi.dot(x_theta), t_xi.dot(x_s), -t_xi.dot(t_xi), -t_xi.dot(t_eta),            //
            t_eta.dot(x_theta), t_eta.dot(x_s), -t_eta.dot(t_xi), t_eta_eta.dot(k.d) - t_eta.dot(t_eta);
        return Fp;
    }

    // dF/dt at fixed p (the bodies move, the parameters do not): F_q v
    Vec4 rate_at_fixed_p(const Contact& k, const mbd::SpatialBody& bi, const mbd::SpatialBody& bj) const {
        const Vec3& wi = bi.omega_bar;
        const Vec3& wj = bj.omega_bar;
        const Vec3 ndot = bi.A * wi.cross(k.nu_bar);
        const Vec3 w = bj.point_velocity(k.x_w_bar) - bi.point_velocity(k.x_r_bar);
        const Vec3 e_theta = bj.A * k.e_theta_bar, x_s = bj.A * k.x_s_bar;
        return Vec4(ndot.dot(e_theta) + k.n.dot(bj.A * wj.cross(k.e_theta_bar)),
                    ndot.dot(x_s) + k.n.dot(bj.A * wj.cross(k.x_s_bar)),
                    (bi.A * wi.cross(k.t_xi_bar)).dot(k.d) + (bi.A * k.t_xi_bar).dot(w),
                    (bi.A * wi.cross(k.t_eta_bar)).dot(k.d) + (bi.A * k.t_eta_bar).dot(w));
    }

    // Least squares where F_p is rank deficient (a line contact): the minimum-norm step.
    static Eigen::CompleteOrthogonalDecomposition<Mat4> decompose(const Mat4& Fp) {
        Eigen::CompleteOrthogonalDecomposition<Mat4> cod(Fp);
        cod.setThreshold(1e-12);
        return cod;
    }

    // F1, F2 are dimensionless, F3, F4 lengths: weighted by the wheel's radius for the line search.
    double merit(const Vec4& F) const {
        return Vec4(F[0], F[1], F[2] / length_, F[3] / length_).squaredNorm();
    }

    // The starting guess: the wheel section over the track's centre line, at its lowest point
    // towards the head; then Newton on F(p) = 0 with a backtracking line search.
    Search solve(const mbd::SpatialBody& bi, const mbd::SpatialBody& bj) const {
        const Vec3 o = bi.point(o_), T = bi.A * A_m_.col(0), U = bi.A * A_m_.col(2);
        const Vec3 centre = bj.point(c_), axle = bj.A * a_;
        const Vec3 on_centre_line = o + T * T.dot(centre - o);
        double s0 = wheel_->clamp(axle.dot(on_centre_line - centre));
        {
            // the wheel section whose normal opposes the head's normal over the centre line:
            // nu_w = e - r' a (normalized) = -nu_r gives r' = -(nu_w . a) / |nu_w - (nu_w . a) a|
            const double eta = rail_->clamp(A_m_.col(1).dot(bi.A.transpose() * (on_centre_line - bi.R) - o_));
            const double h1 = rail_->at(eta).f1;
            const Vec3 nu_r = bi.A * (A_m_ * Vec3(0.0, -h1, 1.0)).normalized();
            const double along = -nu_r.dot(axle);
            if (std::abs(along) < 1.0) s0 = wheel_->where_slope(-along / std::sqrt(1.0 - along * along), s0);
        }
        const Vec3 b1 = bj.A * b1_, b2 = bj.A * b2_;
        const double theta0 = std::atan2(-b2.dot(U), -b1.dot(U));
        Vec4 p(theta0, s0, 0.0, 0.0);
        const Vec3 start = bj.point(c_ + s0 * a_ + wheel_->at(s0).f * (std::cos(theta0) * b1_ + std::sin(theta0) * b2_));
        const Vec3 local = A_m_.transpose() * (bi.A.transpose() * (start - bi.R) - o_);
        p[2] = local.x();
        // the rail point whose normal opposes the wheel's there (the wheel's outward normal is
        // e - r' a, so the head's slope is h' = -(nu_w . y) / (nu_w . z) in the rail frame)
        const CurveValue r0 = wheel_->at(s0);
        const Vec3 nu_w = A_m_.transpose() * (bi.A.transpose() * (bj.A * ((std::cos(theta0) * b1_ + std::sin(theta0) * b2_) - r0.f1 * a_)));
        p[3] = nu_w.z() < 0.0 ? rail_->where_slope(-nu_w.y() / nu_w.z(), rail_->clamp(local.y())) : rail_->clamp(local.y());
        Contact k = at(p, bi, bj);
        Vec4 F = residual(k, bi, bj);
        double m = merit(F);
        for (int iteration = 0; iteration < 60 && m > 0.0; ++iteration) {
            const Vec4 step = decompose(jacobian(k, bi, bj)).solve(F);
            if (!step.allFinite()) break;
            if (step.lpNorm<Eigen::Infinity>() <= 1e-15 * (1.0 + p.lpNorm<Eigen::Infinity>())) {
                p -= step;  // converged: the last step is below round-off
                break;
            }
            bool improved = false;
            double alpha = 1.0;
            for (int halving = 0; halving < 30 && !improved; ++halving, alpha *= 0.5) {
                const Vec4 trial = p - alpha * step;
                const Contact kt = at(trial, bi, bj);
                const Vec4 Ft = residual(kt, bi, bj);
                const double mt = merit(Ft);
                if (std::isfinite(mt) && mt < m) {
                    p = trial;
                    k = kt;
                    F = Ft;
                    m = mt;
                    improved = true;
                }
            }
            if (!improved) break;  // F is at round-off level, or no point of the profiles solves F = 0
        }
        return {p, m};
    }

    std::unique_ptr<const ProfileCurve> wheel_, rail_;
    Vec3 o_;
    Mat3 A_m_;
    Vec3 c_, a_, b1_, b2_;
    double length_ = 1.0;
};

std::unique_ptr<mbd::Joint> make_wheel_rail(const mbd::JointSpec& spec) {
    const std::string who = "wheel_rail '" + spec.name + "'";
    mbd::spatial::require_spatial_pair(spec, "a wheel's tread on a rail's head; in a planar scene use a 'cam' joint (a roller "
                                    "on a profile)", "[rail, wheel]");
    const mbd::Params& p = spec.params;
    const mbd::BodyInfo& wheel_body = spec.bodies[1];
    // world at t = 0 -> wheel body axes
    Vec3 centre = Vec3::Zero();
    if (p.has("wheel_centre"))
        centre = wheel_body.orientation.transpose() * (Vec3(p.vector("wheel_centre", 3)) - wheel_body.position);
    Vec3 axle = spec.markers[1].A_bar.col(1);
    if (p.has("axle")) {
        const Vec3 world = p.vector("axle", 3);
        if (!(world.norm() > 0.0)) p.at("axle").fail(who + ": 'axle' must not be zero");
        axle = wheel_body.orientation.transpose() * world.normalized();
    }
    auto wheel = mbd::wheel_rail::read_wheel_profile(p, who);
    auto rail = mbd::wheel_rail::read_rail_profile(p, who);
    if (wheel->straight() && rail->straight() && wheel->at(0.0).f1 != 0.0)
        p.at("rail").fail(who + ": a conical wheel on a flat head touches at an edge, not at a point; give the rail an "
                                "'arc' or 'spline' head, or the wheel a 'spline' profile");
    return std::make_unique<WheelRail>(std::move(wheel), std::move(rail), spec.markers[0], centre, axle);
}

}  // namespace

MBD_JOINT_PLUGIN(wheel_rail, make_wheel_rail)

// The keys of a scene entry (mbd/sdk/plugin_keys.hpp): `mbd plugin check` builds its test scene
// from the examples; docs/scene-format.md is checked against them (tests/test_plugin_keys.cpp).
namespace {
const mbd::PluginKey wheel_rail_keys[] = {
    {"wheel", "the tread's profile, a map with type: cone (radius, cone_angle, width: the tread's width, default 2 radius) or spline (points)", nullptr, "{type: cone, radius: 0.45, cone_angle: 0.05, width: 10}"},
    {"rail", "the head's profile, a map with type: flat, arc (radius) or spline (points)", nullptr, "{type: arc, radius: 0.3}"},
    {"wheel_centre", "the origin of s on the axle, world at t = 0", "the wheel's mass centre", "[0.8, -0.2, 0.3]"},
    {"axle", "the direction of +s, world at t = 0", "the frame's y axis", "[0.1, 1, 0.2]"},
    {}};
}  // namespace

MBD_JOINT_KEYS(wheel_rail, "a wheel's tread (body j) on a rail's head (body i)", mbd::kTwoBodies, mbd::kSpatialOnly, wheel_rail_keys)
