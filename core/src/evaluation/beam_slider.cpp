// The beam_slider joint (beam_slider.hpp).
//
// Derivation of gamma. With C = N^T d, d = r_P - r(q, s*), and N^T r_s = 0 at every state
// (the normals are across the tangent at s*),
//     Cdot  = Ndot^T d + N^T (ddot) = Ndot^T d + N^T w,     ddot = w - r_s sdot,
// since N^T r_s sdot = 0. Differentiating once more,
//     Cddot = Nddot^T d + Ndot^T (w - r_s sdot) + Ndot^T w + N^T wdot,
//     wdot  = J_P vdot_P + a_P - S vdot - a_S - rdot_s sdot,
// and Ndot^T r_s = -N^T (rdot_s + r_ss sdot) (the rate of N^T r_s = 0), so the rdot_s sdot terms
// cancel and
//     Cddot = N^T [J_P, -S] vdot + 2 Ndot^T w + sdot^2 N^T r_ss + N^T (a_P - a_S) + Nddot^T d.
// On the manifold (d = 0) the last term vanishes, which gives gamma of beam_slider.hpp.
#include "evaluation/beam_slider.hpp"

#include "evaluation/curve_joint.hpp"

#include <mbd/sdk/body_curve.hpp>
#include <mbd/sdk/domain_error.hpp>
#include <mbd/sdk/rotation.hpp>
#include <mbd/sdk/text.hpp>

#include <cmath>
#include <limits>
#include <string>

namespace mbd {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The unit normals across the unit tangent t and their rates for the tangent's rate tdot.
// Planar: the tangent turned by +90 degrees. Spatial: n1 = (a x t) / |a x t| with a the world
// axis least along t (|a x t| >= sqrt(2/3)), n2 = t x n1; the choice of a may change between
// evaluations, which turns the two rows within the same plane across t (the same constraint).
struct Normals {
    int count = 1;
    Vec3 n[2], ndot[2];
};

Normals normals_across(const Vec3& t, const Vec3& tdot, bool planar) {
    Normals out;
    if (planar) {
        out.n[0] = Vec3(-t.y(), t.x(), 0.0);
        out.ndot[0] = Vec3(-tdot.y(), tdot.x(), 0.0);
        return out;
    }
    out.count = 2;
    int axis = 0;
    for (int k = 1; k < 3; ++k)
        if (std::abs(t[k]) < std::abs(t[axis])) axis = k;
    const Vec3 a = Vec3::Unit(axis);
    const Vec3 u = a.cross(t);
    const double length = u.norm();
    out.n[0] = u / length;
    const Vec3 udot = a.cross(tdot);
    out.ndot[0] = (udot - out.n[0] * out.n[0].dot(udot)) / length;
    out.n[1] = t.cross(out.n[0]);
    out.ndot[1] = tdot.cross(out.n[0]) + t.cross(out.ndot[0]);
    return out;
}

// The collar's point P: its position, velocity and acceleration at vdot = 0.
struct CollarPoint {
    Vec3 r = Vec3::Zero(), rdot = Vec3::Zero(), bias = Vec3::Zero();
};

class BeamSlider final : public CurveJoint {
public:
    // along: the collar keeps the angle `offset` to the tangent (planar; a sleeve)
    BeamSlider(Dimension dimension, const Vec3& u_bar, bool along, double offset)
        : planar_(dimension == Dimension::Planar), along_(along), offset_(offset), u_bar_(u_bar) {}

    int rows() const override { return (planar_ ? 1 : 2) + (along_ ? 1 : 0); }
    std::string row_name(int row) const override {
        if (along_ && row == 1) return "tangent angle";
        return planar_ ? "normal" : (row == 0 ? "normal 1" : "normal 2");
    }
    double row_period(int row) const override { return along_ && row == 1 ? 2 * kPi : 0.0; }

    void evaluate_on_curve(const BodyStates& bodies, const BodyCurve& curve, const Eigen::VectorXd& q,
                           const Eigen::VectorXd& v, ConstraintEval& out,
                           Eigen::Ref<Eigen::MatrixXd> J_curve) const override {
        const CollarPoint P = collar_point(bodies);
        CurvePoint c;
        const double s = closest_parameter(curve, q, v, P.r, c);
        const Vec3 d = P.r - c.r;
        const Vec3 w = P.rdot - c.rdot;
        const double g = c.r_s.squaredNorm();
        const double sdot = (w.dot(c.r_s) + d.dot(c.rdot_s)) / (g - d.dot(c.r_ss));
        const double length = std::sqrt(g);
        const Vec3 t = c.r_s / length;
        const Vec3 rs_rate = c.rdot_s + c.r_ss * sdot;  // the total rate of r_s(q, s*)
        const Vec3 tdot = (rs_rate - t * t.dot(rs_rate)) / length;
        const Normals N = normals_across(t, tdot, planar_);
        const int nvb = planar_ ? 3 : 6;
        for (int i = 0; i < N.count; ++i) {
            const Vec3& n = N.n[i];
            out.C[i] = n.dot(d);
            add_collar_row(bodies, n, out.J.row(i).segment(nvb, nvb));
            curve.add_curve_jacobian(q, s, -n, J_curve, i);
            out.gamma[i] = -(2.0 * N.ndot[i].dot(w) + sdot * sdot * n.dot(c.r_ss) + n.dot(P.bias - c.bias));
        }
        if (along_) tangent_angle_row(bodies, curve, q, s, c, P, w, sdot, out, J_curve);
    }

    // The frame at s*: x along the tangent, y (and z) the rows' normals; the normal rows see the
    // curve's point move with -N^T Rdot and do not see the frame turn.
    void curve_frame(const BodyStates& bodies, const BodyCurve& curve, const Eigen::VectorXd& q,
                     const Eigen::VectorXd& v, Mat3& A, Vec3& R, Eigen::MatrixXd& J_frame) const override {
        CurvePoint c;
        closest_parameter(curve, q, v, collar_point(bodies).r, c);
        const Vec3 t = c.r_s.normalized();
        const Normals N = normals_across(t, Vec3::Zero(), planar_);
        A.col(0) = t;
        A.col(1) = N.n[0];
        A.col(2) = planar_ ? Vec3::UnitZ() : N.n[1];
        R = c.r;
        J_frame.setZero(rows(), planar_ ? 3 : 6);
        for (int i = 0; i < N.count; ++i) J_frame.row(i).head(planar_ ? 2 : 3) = -N.n[i].head(planar_ ? 2 : 3).transpose();
        if (along_) {  // the sleeve's row sees the frame turn (-1) and the point move along r_s (tangent_angle_row)
            const double g = c.r_s.squaredNorm(), kappa = c.r_s.x() * c.r_ss.y() - c.r_s.y() * c.r_ss.x();
            J_frame.row(1) << kappa / (g * g) * c.r_s.x(), kappa / (g * g) * c.r_s.y(), -1.0;
        }
    }

private:
    // The sleeve's row (planar), C = theta_collar - phi(s*) - offset with phi = atan2(r_s) the
    // tangent's angle. With rho = rdot_s + r_ss sdot the tangent's rate, phidot = (r_s x rho) / g
    // and sdot = r_s . w / g on the manifold, so over v
    //     J = e_theta - (k x r_s)^T S_s / g - kappa~ r_s^T [J_P, -S] / g^2,   kappa~ = r_s x r_ss,
    // and differentiating once more (sddot_0 from the second rate of the closest-point condition
    // (r_P - r) . r_s = 0 at vdot = 0),
    //     gamma = phiddot at vdot = 0 = (r_s x (bias_s + 2 rdot_ss sdot + r_sss sdot^2 + r_ss sddot_0)) / g
    //             - 2 (r_s x rho)(r_s . rho) / g^2,
    //     sddot_0 = (r_s . (a_P - a_S - rdot_s sdot) + w . rho + ddot . rdot_s - sdot (2 r_s . rho - ddot . r_ss)) / g,
    // ddot = w - r_s sdot the rate of d.
    void tangent_angle_row(const BodyStates& bodies, const BodyCurve& curve, const Eigen::VectorXd& q, double s,
                           const CurvePoint& c, const CollarPoint& P, const Vec3& w, double sdot, ConstraintEval& out,
                           Eigen::Ref<Eigen::MatrixXd> J_curve) const {
        auto cross = [](const Vec3& a, const Vec3& b) { return a.x() * b.y() - a.y() * b.x(); };
        const int row = 1;
        const PlanarBody& collar = bodies.planar(1);
        const double g = c.r_s.squaredNorm(), kappa = cross(c.r_s, c.r_ss);
        const double phi = std::atan2(c.r_s.y(), c.r_s.x());
        out.C[row] = std::remainder(collar.theta - phi - offset_, 2 * kPi);
        auto collar_row = out.J.row(row).segment(3, 3);
        add_collar_row(bodies, -kappa / (g * g) * c.r_s, collar_row);
        collar_row(2) += 1.0;
        curve.add_curve_slope_jacobian(q, s, -Vec3(-c.r_s.y(), c.r_s.x(), 0.0) / g, J_curve, row);
        curve.add_curve_jacobian(q, s, kappa / (g * g) * c.r_s, J_curve, row);
        const Vec3 rho = c.rdot_s + c.r_ss * sdot;
        const Vec3 ddot = w - c.r_s * sdot;
        const double sddot0 = (c.r_s.dot(P.bias - c.bias - c.rdot_s * sdot) + w.dot(rho) + ddot.dot(c.rdot_s) -
                               sdot * (2.0 * c.r_s.dot(rho) - ddot.dot(c.r_ss))) / g;
        const Vec3 rho_rate0 = c.bias_s + 2.0 * sdot * c.rdot_ss + sdot * sdot * c.r_sss + sddot0 * c.r_ss;
        out.gamma[row] = cross(c.r_s, rho_rate0) / g - 2.0 * cross(c.r_s, rho) * c.r_s.dot(rho) / (g * g);
    }

    CollarPoint collar_point(const BodyStates& bodies) const {
        CollarPoint P;
        if (planar_) {
            const PlanarBody& b = bodies.planar(1);
            const Vec2 u = u_bar_.head<2>();
            P.r.head<2>() = b.point(u);
            P.rdot.head<2>() = b.point_velocity(u);
            P.bias.head<2>() = -b.omega * b.omega * (b.A * u);
        } else {
            const SpatialBody& b = bodies.spatial(1);
            P.r = b.point(u_bar_);
            P.rdot = b.point_velocity(u_bar_);
            P.bias = b.A * b.omega_bar.cross(b.omega_bar.cross(u_bar_));
        }
        return P;
    }

    // n^T J_P: planar [n, n . A_theta u]; spatial [n, u x (A^T n)] (v_P = Rdot - A u~ wbar)
    template <class Row>
    void add_collar_row(const BodyStates& bodies, const Vec3& n, Row row) const {
        if (planar_) {
            const PlanarBody& b = bodies.planar(1);
            row(0) = n.x();
            row(1) = n.y();
            row(2) = n.head<2>().dot(b.A_theta * u_bar_.head<2>());
        } else {
            const SpatialBody& b = bodies.spatial(1);
            row.template head<3>() = n.transpose();
            row.template tail<3>() = u_bar_.cross(b.A.transpose() * n).transpose();
        }
    }

    // s*: the closest point of the curve to r_P (top of beam_slider.hpp); c is the curve there.
    double closest_parameter(const BodyCurve& curve, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                             const Vec3& r_P, CurvePoint& c) const {
        const int pieces = curve.curve_pieces();
        const double first = curve.curve_break(0), last = curve.curve_break(pieces);
        const double span = last - first;
        double s = first, nearest = std::numeric_limits<double>::infinity();
        constexpr int kSamples = 4;  // intervals per piece; Newton starts from the nearest sample
        for (int k = 0; k < pieces; ++k) {
            const double a = curve.curve_break(k), b = curve.curve_break(k + 1);
            for (int i = 0; i <= kSamples; ++i) {
                const double x = a + (b - a) * i / kSamples;
                curve.curve_point(q, v, x, c);
                const double distance = (r_P - c.r).squaredNorm();
                if (distance < nearest) {
                    nearest = distance;
                    s = x;
                }
            }
        }
        for (int iteration = 0;; ++iteration) {
            curve.curve_point(q, v, s, c);
            const Vec3 d = r_P - c.r;
            const double slope = d.dot(c.r_ss) - c.r_s.squaredNorm();  // dphi/ds, < 0 at a minimum
            if (!(slope < 0.0) || iteration == 50)
                throw DomainError("the collar's point has no unique closest point on the flexible body's centre line near "
                                  "s = " + format_number(s) + " (it lies at or beyond the centre of curvature there)");
            const double step = -d.dot(c.r_s) / slope;
            s += step;
            if (std::abs(step) <= 1e-14 * span) break;
        }
        curve.curve_point(q, v, s, c);
        const double slack = 1e-12 * span;
        if (!(s >= first - slack && s <= last + slack))
            throw DomainError("the collar left the flexible body: its closest point is at s = " + format_number(s) +
                              ", outside the centre line [" + format_number(first) + ", " + format_number(last) + "]");
        return s;
    }

    bool planar_;
    bool along_;
    double offset_;
    Vec3 u_bar_;  // the collar's point, its own axes
};

std::string quote(const std::string& text) { return "'" + text + "'"; }

std::string joint_label(const JointInstance& joint) {
    return "joint " + quote(joint.name) + " (type " + joint.type + ")";
}

}  // namespace

std::unique_ptr<Joint> make_beam_slider(const JointSpec& spec) {
    const std::string orientation = spec.params.string("orientation", "free");
    if (orientation != "free" && orientation != "tangent")
        spec.params.at("orientation").fail(spec.params.owner() + ": 'orientation' must be free (the collar turns "
                                                                  "freely) or tangent (it keeps its angle to the "
                                                                  "beam's tangent), not '" + orientation + "'");
    const bool along = orientation == "tangent";
    if (along && spec.dimension != Dimension::Planar)
        spec.params.at("orientation").fail(spec.params.owner() + ": 'orientation: tangent' is planar only; in a "
                                                                  "spatial scene the collar turns freely");
    // the collar's angle to the tangent at t = 0 (the curve's slot: the material frame at s0)
    const double offset = spec.bodies.at(1).angle - spec.bodies.at(0).angle;
    return std::make_unique<BeamSlider>(spec.dimension, spec.markers.at(CurveJoint::kCurveSlot + 1).u_bar, along,
                                        offset);
}

void check_beam_slider(const Model& model, const JointInstance& joint) {
    const std::string what = joint_label(joint);
    const bool curve_first = joint.flexible.size() == 1 && joint.flexible.front().slot == CurveJoint::kCurveSlot;
    if (joint.bodies.size() != 2 || !curve_first)
        throw InputError(joint.where, what + ": 'bodies' must be [{body: BEAM, at: s0}, COLLAR]: first the flexible "
                                             "body along which the collar slides (the collar starts at its arc "
                                             "length s0), then the collar, a rigid body or the ground");
    const FlexibleBodyInstance& body = model.flexible_bodies.at(joint.flexible.front().body);
    if (!dynamic_cast<const BodyCurve*>(body.body.get()))
        throw InputError(joint.where, what + ": flexible body " + quote(body.name) + " (type " + body.type +
                                          ") has no centre line to slide along; use an ancf_cable or ancf_beam");
}

}  // namespace mbd
