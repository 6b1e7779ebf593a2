// The sphere_surface joint plugin (spatial; book Sec. 8.6, Eqs. 8.50-8.74): a sphere of radius r
// (centre P fixed on body j; r = 0: a point) touching a profiled surface fixed on body i, sliding
// and rolling freely (no friction: the contact only pushes along the normal).
//
// The surface is a graph over the joint frame on body i (origin o, axes A_m; its z axis is the
// surface's "up"): x_bar(u, v) = o + A_m [u, v, f(u, v)], with the surface parameters (u, v) of
// the contact point the book's non-generalized coordinates s (Eq. 8.50). As in the cam joint they
// are eliminated inside the joint: for any body state they are the foot of the perpendicular from
// the sphere's centre to the surface,
//     H(s) = X_s^T (p_bar - x_bar(s)) = 0,   X_s = [x_u, x_v],   p_bar = A_i^T (r_P - R_i),
// found by Newton from (u, v) of p_bar, and the joint keeps ONE row, the normal gap
//     g = n . (r_P - r_c) - r,   n = A_i nu_bar(s) (unit normal, up),   r_c = R_i + A_i x_bar(s),
// whose multiplier is the normal contact force: the one multiplier per contact that
// C_s^T lambda = 0 leaves of the book's five equations (Eq. 8.72 and the text after it). The gap
// is stationary in s at the foot point, so its Jacobian at fixed s is exact (envelope theorem):
//     J = [ -n^T | -(x_bar x nu_bar)^T | n^T | (u_bar_P x A_j^T n)^T ]      (columns dR, dpi_bar)
// and, with w = rdot_P - (Rdot_i + A_i (wbar_i x x_bar)),
//     gamma = -( ndot . w + n . (A_j wbar_j~^2 u_bar_P - A_i wbar_i~^2 x_bar - A_i (wbar_i x X_s sdot)) ),
//     ndot  = A_i (wbar_i x nu_bar + nu_bar_s sdot),   sdot = -H_s^-1 X_s^T pdot_bar,
//     H_s[a][b] = x_ab . (p_bar - x_bar) - x_a . x_b,   pdot_bar = A_i^T (rdot_P - Rdot_i) - wbar_i x p_bar.
// Surfaces (`surface:` map, `type`):
//   bowl       — a spherical cap of radius R, bottom at the frame origin, opening along +z:
//                f = R - sqrt(R^2 - u^2 - v^2) (a ball inside a spherical bowl, book Sec. 8.6);
//   paraboloid — f = (k_u u^2 + k_v v^2) / 2, `curvatures: [k_u, k_v]` (a saddle when of opposite
//                signs; k_v = 0 with k_u != 0 is a trough).
// The sphere must stay on the up side, within the surface's domain, and its radius below the
// surface's least radius of curvature there. The contact pushes while lambda < 0
// (compression_sign): a run warns where the ball would leave the surface.
// Scene keys: bodies: [surface body, ball]; point and axis: the surface frame on body i (axis =
// its up direction, world, at t = 0); radius: r >= 0; ball_point: [x, y, z] the sphere's centre
// in body j axes (default the mass centre); surface: {...}.
#include <mbd/sdk/contact_joint.hpp>
#include <mbd/sdk/plugin.hpp>
#include <mbd/sdk/plugin_keys.hpp>
#include <mbd/sdk/spatial_primitives.hpp>
#include <mbd/sdk/rotation.hpp>

#include <Eigen/Dense>

#include <cmath>
#include <memory>
#include <string>

namespace {

using mbd::Mat3;
using mbd::Vec3;
using Mat2 = Eigen::Matrix2d;
using Vec2 = Eigen::Vector2d;

// f and its derivatives up to the second at (u, v).
struct Height {
    double f = 0, fu = 0, fv = 0, fuu = 0, fuv = 0, fvv = 0;
};

class Surface {
public:
    virtual ~Surface() = default;
    virtual Height at(double u, double v) const = 0;
};

class Bowl final : public Surface {
public:
    explicit Bowl(double R) : R_(R) {}
    Height at(double u, double v) const override {
        const double w2 = R_ * R_ - u * u - v * v, w = std::sqrt(w2);
        return {R_ - w, u / w, v / w, (w2 + u * u) / (w2 * w), u * v / (w2 * w), (w2 + v * v) / (w2 * w)};
    }

private:
    double R_;
};

class Paraboloid final : public Surface {
public:
    Paraboloid(double ku, double kv) : ku_(ku), kv_(kv) {}
    Height at(double u, double v) const override {
        return {0.5 * (ku_ * u * u + kv_ * v * v), ku_ * u, kv_ * v, ku_, 0.0, kv_};
    }

private:
    double ku_, kv_;
};

// The surface point at s = (u, v) in body i axes with its derivatives and unit normal.
struct SurfacePoint {
    Vec3 x, xu, xv, xuu, xuv, xvv;
    Vec3 nu, nu_u, nu_v;
};

class SphereSurface final : public mbd::ContactJoint {
public:
    SphereSurface(std::unique_ptr<const Surface> surface, const mbd::Marker& frame, const Vec3& ball_point, double r)
        : surface_(std::move(surface)), o_(frame.u_bar), A_m_(frame.A_bar), u_P_(ball_point), r_(r) {}

    void evaluate(const mbd::BodyStates& b, mbd::ConstraintEval& out) const override {
        clear(out);
        const mbd::SpatialBody& bi = b.spatial(0);
        const mbd::SpatialBody& bj = b.spatial(1);
        const Vec3 r_P = bj.point(u_P_), rdot_P = bj.point_velocity(u_P_);
        const Vec3 p = bi.A.transpose() * (r_P - bi.R);
        const Vec3 pdot = bi.A.transpose() * (rdot_P - bi.Rdot) - bi.omega_bar.cross(p);
        const Vec2 s = foot_point(p);
        const SurfacePoint c = at(s);
        const Mat2 Hs = hessian(c, p);
        const Vec2 sdot = -Hs.inverse() * Vec2(c.xu.dot(pdot), c.xv.dot(pdot));
        const Vec3 n = bi.A * c.nu, r_c = bi.point(c.x);
        const Vec3 x_rate = c.xu * sdot.x() + c.xv * sdot.y();
        const Vec3 w = rdot_P - (bi.Rdot + bi.A * bi.omega_bar.cross(c.x));
        const Vec3 ndot = bi.A * (bi.omega_bar.cross(c.nu) + c.nu_u * sdot.x() + c.nu_v * sdot.y());
        const Vec3& wi = bi.omega_bar;
        const Vec3& wj = bj.omega_bar;
        out.C[0] = n.dot(r_P - r_c) - r_;
        out.J.block<1, 3>(0, 0) = -n.transpose();
        out.J.block<1, 3>(0, 3) = -c.x.cross(c.nu).transpose();
        out.J.block<1, 3>(0, 6) = n.transpose();
        out.J.block<1, 3>(0, 9) = u_P_.cross(bj.A.transpose() * n).transpose();
        out.gamma[0] = -(ndot.dot(w) + n.dot(bj.A * wj.cross(wj.cross(u_P_)) - bi.A * wi.cross(wi.cross(c.x)) -
                                             bi.A * wi.cross(x_rate)));
    }

private:
    SurfacePoint at(const Vec2& s) const {
        const Height h = surface_->at(s.x(), s.y());
        SurfacePoint c;
        c.x = o_ + A_m_ * Vec3(s.x(), s.y(), h.f);
        c.xu = A_m_ * Vec3(1, 0, h.fu);
        c.xv = A_m_ * Vec3(0, 1, h.fv);
        c.xuu = A_m_ * Vec3(0, 0, h.fuu);
        c.xuv = A_m_ * Vec3(0, 0, h.fuv);
        c.xvv = A_m_ * Vec3(0, 0, h.fvv);
        const Vec3 N = c.xu.cross(c.xv);
        const double length = N.norm();
        c.nu = N / length;
        // d nu = (dN - (nu . dN) nu) / |N|
        const Vec3 Nu = c.xuu.cross(c.xv) + c.xu.cross(c.xuv), Nv = c.xuv.cross(c.xv) + c.xu.cross(c.xvv);
        c.nu_u = (Nu - c.nu.dot(Nu) * c.nu) / length;
        c.nu_v = (Nv - c.nu.dot(Nv) * c.nu) / length;
        return c;
    }
    static Mat2 hessian(const SurfacePoint& c, const Vec3& p) {
        const Vec3 d = p - c.x;
        Mat2 H;
        H << c.xuu.dot(d) - c.xu.dot(c.xu), c.xuv.dot(d) - c.xu.dot(c.xv), c.xuv.dot(d) - c.xv.dot(c.xu),
            c.xvv.dot(d) - c.xv.dot(c.xv);
        return H;
    }
    // Newton on H(s) = X_s^T (p - x(s)) = 0 from the frame coordinates (u, v) of p.
    Vec2 foot_point(const Vec3& p) const {
        const Vec3 local = A_m_.transpose() * (p - o_);
        Vec2 s(local.x(), local.y());
        for (int iteration = 0; iteration < 60; ++iteration) {
            const SurfacePoint c = at(s);
            const Vec2 H(c.xu.dot(p - c.x), c.xv.dot(p - c.x));
            const Vec2 step = hessian(c, p).partialPivLu().solve(H);
            if (!step.allFinite()) break;
            s -= step;
            if (step.lpNorm<Eigen::Infinity>() <= 1e-15 * (1.0 + s.lpNorm<Eigen::Infinity>())) break;
        }
        return s;
    }

    std::unique_ptr<const Surface> surface_;
    Vec3 o_;
    Mat3 A_m_;
    Vec3 u_P_;
    double r_;
};

std::unique_ptr<mbd::Joint> make_sphere_surface(const mbd::JointSpec& spec) {
    const std::string who = "sphere_surface '" + spec.name + "'";
    mbd::spatial::require_spatial_pair(spec, "in a planar scene use a 'cam' joint (a roller on a profile)",
                              "[surface body, ball]");
    const mbd::Params& p = spec.params;
    const double radius = p.non_negative("radius", 0.0);
    Vec3 ball_point = Vec3::Zero();
    if (p.has("ball_point")) ball_point = p.vector("ball_point", 3);
    const mbd::Params s = p.child("surface");
    const std::string type = s.string("type");
    std::unique_ptr<const Surface> surface;
    if (type == "bowl") {
        const double R = s.positive("radius");
        if (!(radius < R)) s.at("radius").fail(who + ": the bowl's 'radius' must exceed the ball's radius " + p.at("radius").text);
        surface = std::make_unique<Bowl>(R);
    } else if (type == "paraboloid") {
        const Eigen::VectorXd k = s.vector("curvatures", 2);
        if (!k.allFinite()) s.at("curvatures").fail(who + ": 'curvatures' must be finite");
        surface = std::make_unique<Paraboloid>(k[0], k[1]);
    } else {
        s.at("type").fail(who + ": unknown surface type '" + type + "' (bowl or paraboloid)");
    }
    return std::make_unique<SphereSurface>(std::move(surface), spec.markers[0], ball_point, radius);
}

}  // namespace

MBD_JOINT_PLUGIN(sphere_surface, make_sphere_surface)

// The keys of a scene entry (mbd/sdk/plugin_keys.hpp): `mbd plugin check` builds its test scene
// from the examples; docs/scene-format.md is checked against them (tests/test_plugin_keys.cpp).
namespace {
const mbd::PluginKey sphere_surface_keys[] = {
    {"surface", "the surface, a map with type: bowl (radius) or paraboloid (curvatures)", nullptr, "{type: bowl, radius: 3}"},
    {"radius", "the sphere's radius (m), >= 0 (0: a point)", "0", "0.1", nullptr, true},
    {"ball_point", "the sphere's centre in body j's axes", "body j's mass centre", "[0, 0, 0.1]"},
    {}};
}  // namespace

MBD_JOINT_KEYS(sphere_surface, "a sphere on body j sliding on a surface z = f(u, v) of body i", mbd::kTwoBodies, mbd::kSpatialOnly, sphere_surface_keys)
