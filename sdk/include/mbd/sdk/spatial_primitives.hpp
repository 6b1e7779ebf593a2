// Spatial constraint primitives (book Sec. 7.10, Remarks at L11362: every spatial
// joint is built from r_P^i - r_P^j = c, v^iT v^j = 0 and v^iT r_P^ij = 0 and
// their derivatives, "a computer library").
//
// Everything is written against the virtual motion of the joint's two bodies,
//     [dR_i, dpi_bar_i, dR_j, dpi_bar_j]   (12 columns, body i first),
// i.e. the velocity vector v = [Rdot_i, wbar_i, Rdot_j, wbar_j] of the SDK, and
// every result satisfies  xddot = J vdot - gamma  (book Eq. 3.124, gamma = Q_d).
//
// Kinematics of body-fixed quantities (wbar in body axes):
//   direction a = A a_bar:       J_pi = -A a_bar~,   adot = A (wbar x a_bar),
//                                addot = -A a_bar~ wbar_dot + A wbar~ wbar~ a_bar
//   point r = R + A u_bar:       J = [I, -A u_bar~], rdot = Rdot + A (wbar x u_bar),
//                                rddot = Rddot - A u_bar~ wbar_dot + A wbar~ wbar~ u_bar
// The primitives are products/differences of these (Kin3 algebra below), which
// expands to exactly the table of the joints digest, Sec. 4.1:
//   SPH  d = r_P^i - r_P^j                (Eqs. 7.159-7.166)
//   DOT1 a_i . a_j                        (Eqs. 7.168-7.170, 7.177-7.182)
//   DOT2 a_i . d                          (Eqs. 7.169, 7.178)
//   DIST d . d - L^2                      (Eqs. 7.171-7.174)
#pragma once

#include <mbd/sdk/body_state.hpp>
#include <mbd/sdk/joint.hpp>
#include <mbd/sdk/params.hpp>
#include <mbd/sdk/rotation.hpp>

#include <Eigen/Core>

#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace mbd {
namespace spatial {

using Row12 = Eigen::Matrix<double, 1, 12>;
using Jac3x12 = Eigen::Matrix<double, 3, 12>;

// A world 3-vector x(q) of the two bodies with its kinematics:
// value x, rate xdot = J v, Jacobian J (3 x 12) and the velocity-quadratic part
// of the acceleration, xddot = J vdot + quad (so gamma_x = -quad).
struct Kin3 {
    Vec3 value = Vec3::Zero();
    Vec3 rate = Vec3::Zero();
    Jac3x12 J = Jac3x12::Zero();
    Vec3 quad = Vec3::Zero();

    Vec3 gamma() const { return -quad; }
};

inline Kin3 operator-(const Kin3& a, const Kin3& b) {
    Kin3 r;
    r.value = a.value - b.value;
    r.rate = a.rate - b.rate;
    r.J = a.J - b.J;
    r.quad = a.quad - b.quad;
    return r;
}

// A scalar s(q) of the two bodies: value, rate sdot = J v, J (1 x 12) and gamma
// with sddot = J vdot - gamma.
struct Scalar {
    double value = 0.0;
    double rate = 0.0;
    Row12 J = Row12::Zero();
    double gamma = 0.0;
};

// a*x + b*y (the gradient and gamma are linear too).
inline Scalar combine(double a, const Scalar& x, double b, const Scalar& y) {
    Scalar r;
    r.value = a * x.value + b * y.value;
    r.rate = a * x.rate + b * y.rate;
    r.J = a * x.J + b * y.J;
    r.gamma = a * x.gamma + b * y.gamma;
    return r;
}

// x . y of two Kin3 quantities (product rule twice):
//   J = y^T J_x + x^T J_y,  gamma = -(y . quad_x + x . quad_y + 2 xdot . ydot).
inline Scalar dot(const Kin3& x, const Kin3& y) {
    Scalar s;
    s.value = x.value.dot(y.value);
    s.rate = x.rate.dot(y.value) + x.value.dot(y.rate);
    s.J = y.value.transpose() * x.J + x.value.transpose() * y.J;
    s.gamma = -(y.value.dot(x.quad) + x.value.dot(y.quad) + 2.0 * x.rate.dot(y.rate));
    return s;
}

// The joint's two bodies: body i (index 0, columns 0-5) and body j (index 1, columns 6-11).
class Pair {
public:
    Pair(const SpatialBody& body_i, const SpatialBody& body_j) : bodies_{&body_i, &body_j} {}
    explicit Pair(const BodyStates& states) : Pair(states.spatial(0), states.spatial(1)) {}

    const SpatialBody& body(int k) const { return *bodies_[k]; }

    // Body-fixed direction a = A a_bar on body k.
    Kin3 vector(int k, const Vec3& a_bar) const {
        const SpatialBody& b = body(k);
        Kin3 x;
        x.value = b.A * a_bar;
        x.rate = b.A * b.omega_bar.cross(a_bar);
        x.J.block<3, 3>(0, 6 * k + 3) = -b.A * skew(a_bar);
        x.quad = b.A * b.omega_bar.cross(b.omega_bar.cross(a_bar));
        return x;
    }

    // Body-fixed point r = R + A u_bar on body k (u_bar = 0: the mass centre R).
    Kin3 point(int k, const Vec3& u_bar) const {
        const SpatialBody& b = body(k);
        Kin3 x;
        x.value = b.R + b.A * u_bar;
        x.rate = b.Rdot + b.A * b.omega_bar.cross(u_bar);
        x.J.block<3, 3>(0, 6 * k).setIdentity();
        x.J.block<3, 3>(0, 6 * k + 3) = -b.A * skew(u_bar);
        x.quad = b.A * b.omega_bar.cross(b.omega_bar.cross(u_bar));
        return x;
    }

private:
    const SpatialBody* bodies_[2];
};

// ---- the primitives ------------------------------------------------------------

// The primitives below are the Kin3 algebra above written out, each in the body frames
// where that saves work (they run for every joint on every evaluation): for a body-fixed
// direction a = A a_bar and any world vector x,
//     x^T (-A a_bar~) = (a_bar x (A^T x))^T            (the rotational Jacobian block of a . x)
// and for a body-fixed point r = R + A u_bar,  x^T (-A u_bar~) = (u_bar x (A^T x))^T.

// A body-fixed point's or direction's rate and velocity-quadratic acceleration, world frame:
// A (w x u) and A (w x (w x u)).
struct BodyFixedMotion {
    Vec3 rate, quad;
    BodyFixedMotion(const SpatialBody& b, const Vec3& u_bar) {
        const Vec3 w_u = b.omega_bar.cross(u_bar);
        rate = b.A * w_u;
        quad = b.A * b.omega_bar.cross(w_u);
    }
};

// SPH: d = r_P^i - r_P^j (3 rows; book Eqs. 7.159-7.166, Jacobian [I, -A_i u_i~, -I, A_j u_j~]).
inline Kin3 sph(const Pair& pair, const Vec3& u_bar_i, const Vec3& u_bar_j) {
    const SpatialBody& bi = pair.body(0);
    const SpatialBody& bj = pair.body(1);
    const BodyFixedMotion mi(bi, u_bar_i), mj(bj, u_bar_j);
    Kin3 d;
    d.value = bi.R + bi.A * u_bar_i - bj.R - bj.A * u_bar_j;
    d.rate = bi.Rdot + mi.rate - bj.Rdot - mj.rate;
    d.J.block<3, 3>(0, 0).setIdentity();
    d.J.block<3, 3>(0, 3).noalias() = -bi.A * skew(u_bar_i);
    d.J.block<3, 3>(0, 6) = -Mat3::Identity();
    d.J.block<3, 3>(0, 9).noalias() = bj.A * skew(u_bar_j);
    d.quad = mi.quad - mj.quad;
    return d;
}

// DOT1: a_i . a_j for body-fixed a_i on body i and a_j on body j (book Eqs. 7.168-7.170):
// J = [0, a_bar_i x (A_i^T a_j), 0, a_bar_j x (A_j^T a_i)],
// gamma = -(a_j . addot_i + a_i . addot_j + 2 adot_i . adot_j) (quadratic parts).
inline Scalar dot1(const Pair& pair, const Vec3& a_bar_i, const Vec3& a_bar_j) {
    const SpatialBody& bi = pair.body(0);
    const SpatialBody& bj = pair.body(1);
    const Vec3 ai = bi.A * a_bar_i, aj = bj.A * a_bar_j;
    const BodyFixedMotion mi(bi, a_bar_i), mj(bj, a_bar_j);
    Scalar s;
    s.value = ai.dot(aj);
    s.rate = mi.rate.dot(aj) + ai.dot(mj.rate);
    s.J.segment<3>(3) = a_bar_i.cross(bi.A.transpose() * aj).transpose();
    s.J.segment<3>(9) = a_bar_j.cross(bj.A.transpose() * ai).transpose();
    s.gamma = -(aj.dot(mi.quad) + ai.dot(mj.quad) + 2.0 * mi.rate.dot(mj.rate));
    return s;
}

// DOT2: a_i . d with d = r_P^i - r_P^j (book Eqs. 7.169, 7.172, 7.178):
// J = [a_i^T, (a_bar_i x (A_i^T d) + u_bar_i x a_bar_i)^T, -a_i^T, -(u_bar_j x (A_j^T a_i))^T].
inline Scalar dot2(const Pair& pair, const Vec3& a_bar_i, const Vec3& u_bar_i, const Vec3& u_bar_j) {
    const SpatialBody& bi = pair.body(0);
    const SpatialBody& bj = pair.body(1);
    const Vec3 ai = bi.A * a_bar_i;
    const BodyFixedMotion ma(bi, a_bar_i), mi(bi, u_bar_i), mj(bj, u_bar_j);
    const Vec3 d = bi.R + bi.A * u_bar_i - bj.R - bj.A * u_bar_j;
    const Vec3 ddot = bi.Rdot + mi.rate - bj.Rdot - mj.rate;
    Scalar s;
    s.value = ai.dot(d);
    s.rate = ma.rate.dot(d) + ai.dot(ddot);
    s.J.segment<3>(0) = ai.transpose();
    s.J.segment<3>(3) = (a_bar_i.cross(bi.A.transpose() * d) + u_bar_i.cross(a_bar_i)).transpose();
    s.J.segment<3>(6) = -ai.transpose();
    s.J.segment<3>(9) = -u_bar_j.cross(bj.A.transpose() * ai).transpose();
    s.gamma = -(d.dot(ma.quad) + ai.dot(mi.quad - mj.quad) + 2.0 * ma.rate.dot(ddot));
    return s;
}

// DIST: d . d - length^2 (book Eqs. 7.171-7.174; singular at d = 0, prefer SPH).
inline Scalar dist(const Pair& pair, const Vec3& u_bar_i, const Vec3& u_bar_j, double length) {
    const Kin3 d = sph(pair, u_bar_i, u_bar_j);
    Scalar s = dot(d, d);
    s.value -= length * length;
    return s;
}

// s = atan2(D1, D2) from two scalars [derived, not in the book]:
//   sdot  = (D2 D1dot - D1 D2dot) / rho^2,  rho^2 = D1^2 + D2^2
//   J_s   = (D2 J_1 - D1 J_2) / rho^2
//   gamma = (D2 gamma_1 - D1 gamma_2) / rho^2 + 2 sdot (D1 D1dot + D2 D2dot) / rho^2
// (differentiate sdot once more; the D1dot D2dot cross terms cancel).
inline Scalar atan2_of(const Scalar& D1, const Scalar& D2) {
    const double rho2 = D1.value * D1.value + D2.value * D2.value;
    Scalar s;
    s.value = std::atan2(D1.value, D2.value);
    s.rate = (D2.value * D1.rate - D1.value * D2.rate) / rho2;
    s.J = (D2.value * D1.J - D1.value * D2.J) / rho2;
    s.gamma = (D2.value * D1.gamma - D1.value * D2.gamma) / rho2 +
              2.0 * s.rate * (D1.value * D1.rate + D2.value * D2.rate) / rho2;
    return s;
}

// Angle of marker frame j about z_i: atan2(y_i . x_j, x_i . x_j) (two DOT1 values).
// Zero when the frames coincide; positive for a right-hand rotation of j about z_i.
inline Scalar angle_about_z(const Pair& pair, const Marker& mi, const Marker& mj) {
    return atan2_of(dot1(pair, mi.axis_y(), mj.axis_x()), dot1(pair, mi.axis_x(), mj.axis_x()));
}

// Travel of a point of body j along z_i from the joint origin on body i:
// z_i . (r^j - r_P^i), with r^j = R_j + A_j u_bar_j (u_bar_j = 0: the mass centre).
inline Scalar travel_along_z(const Pair& pair, const Marker& mi, const Vec3& u_bar_j) {
    return dot(pair.vector(0, mi.axis_z()), pair.point(1, u_bar_j) - pair.point(0, mi.u_bar));
}

// ---- velocity derivatives of gamma, transposed -----------------------------------

// gamma of every primitive is a sum of terms m . A (w x (w x u)) and (A (w x u)) . x, over body-fixed
// u_bar and world vectors m, x that do not depend on the angular velocity wbar = w of that body.
// Their gradients with respect to w (body axes, as v's rotational components):
//   d/dw [m . A (w x (w x u))] = (w x u) x m' + u x (m' x w),   m' = A^T m
//   d/dw [x . A (w x u)]       = u x (A^T x)
inline Vec3 quad_gradient(const SpatialBody& b, const Vec3& u_bar, const Vec3& m_world) {
    const Vec3 m = b.A.transpose() * m_world;
    return b.omega_bar.cross(u_bar).cross(m) + u_bar.cross(m.cross(b.omega_bar));
}
inline Vec3 rate_gradient(const SpatialBody& b, const Vec3& u_bar, const Vec3& x_world) {
    return u_bar.cross(b.A.transpose() * x_world);
}

// out (12: [Rdot_i, wbar_i, Rdot_j, wbar_j]) += weight(s) times d gamma / d v of each primitive.
using Grad12 = Eigen::Map<Eigen::Matrix<double, 12, 1>>;

// SPH: gamma = -(A_i (w_i x (w_i x u_i)) - A_j (w_j x (w_j x u_j))), 3 rows weighted by mu.
inline void sph_gamma_gradient(const Pair& pair, const Vec3& u_bar_i, const Vec3& u_bar_j, const Vec3& mu, Grad12 out) {
    out.segment<3>(3) -= quad_gradient(pair.body(0), u_bar_i, mu);
    out.segment<3>(9) += quad_gradient(pair.body(1), u_bar_j, mu);
}

// DOT1: gamma = -(a_j . addot_i + a_i . addot_j + 2 adot_i . adot_j) (quadratic parts).
inline void dot1_gamma_gradient(const Pair& pair, const Vec3& a_bar_i, const Vec3& a_bar_j, double weight, Grad12 out) {
    const SpatialBody& bi = pair.body(0);
    const SpatialBody& bj = pair.body(1);
    const Vec3 ai = bi.A * a_bar_i, aj = bj.A * a_bar_j;
    const Vec3 rate_i = bi.A * bi.omega_bar.cross(a_bar_i), rate_j = bj.A * bj.omega_bar.cross(a_bar_j);
    out.segment<3>(3) -= weight * (quad_gradient(bi, a_bar_i, aj) + 2.0 * rate_gradient(bi, a_bar_i, rate_j));
    out.segment<3>(9) -= weight * (quad_gradient(bj, a_bar_j, ai) + 2.0 * rate_gradient(bj, a_bar_j, rate_i));
}

// DOT2: gamma = -(d . addot_i + a_i . (rddot_i - rddot_j) + 2 adot_i . ddot) (quadratic parts),
// ddot = Rdot_i + A_i (w_i x u_i) - Rdot_j - A_j (w_j x u_j): the one primitive with Rdots.
inline void dot2_gamma_gradient(const Pair& pair, const Vec3& a_bar_i, const Vec3& u_bar_i, const Vec3& u_bar_j,
                                double weight, Grad12 out) {
    const SpatialBody& bi = pair.body(0);
    const SpatialBody& bj = pair.body(1);
    const Vec3 ai = bi.A * a_bar_i, adot = bi.A * bi.omega_bar.cross(a_bar_i);
    const Vec3 d = bi.R + bi.A * u_bar_i - bj.R - bj.A * u_bar_j;
    const Vec3 ddot = bi.Rdot + bi.A * bi.omega_bar.cross(u_bar_i) - bj.Rdot - bj.A * bj.omega_bar.cross(u_bar_j);
    out.segment<3>(0) -= 2.0 * weight * adot;
    out.segment<3>(6) += 2.0 * weight * adot;
    out.segment<3>(3) -= weight * (quad_gradient(bi, a_bar_i, d) + quad_gradient(bi, u_bar_i, ai) +
                                   2.0 * rate_gradient(bi, a_bar_i, ddot) + 2.0 * rate_gradient(bi, u_bar_i, adot));
    out.segment<3>(9) += weight * (quad_gradient(bj, u_bar_j, ai) + 2.0 * rate_gradient(bj, u_bar_j, adot));
}

// ---- writing rows ---------------------------------------------------------------

// Rows [row, row + 3) of out (C_t = 0: the primitives do not depend on time).
inline void write(ConstraintEval& out, int row, const Kin3& x) {
    out.C.segment<3>(row) = x.value;
    out.J.block(row, 0, 3, 12) = x.J;
    out.C_t.segment<3>(row).setZero();
    out.gamma.segment<3>(row) = x.gamma();
}
inline void write(ConstraintEval& out, int row, const Scalar& s) {
    out.C[row] = s.value;
    out.J.block(row, 0, 1, 12) = s.J;
    out.C_t[row] = 0.0;
    out.gamma[row] = s.gamma;
}
inline void write(CoordinateEval& out, const Scalar& s, bool periodic) {
    out.value = s.value;
    out.J = s.J;
    out.gamma = s.gamma;
    out.periodic = periodic;
}

// ---- joints as lists of primitives ------------------------------------------------

// Marker axes by index.
enum Axis : int { X = 0, Y = 1, Z = 2 };

// Checks shared by the spatial joints: a spatial scene and exactly two bodies.
// `planar_hint` tells a user of a planar scene what to use instead; `roles`, if given,
// names the two bodies in their order ("[rail, wheel]").
inline void require_spatial_pair(const JointSpec& spec, const std::string& planar_hint,
                                 const std::string& roles = "") {
    const std::string who = "joint '" + spec.name + "'";
    if (spec.dimension != Dimension::Spatial)
        throw InputError(spec.params.location(),
                         who + ": " + spec.type + " is a spatial joint; " + planar_hint);
    if (spec.bodies.size() != 2 || spec.markers.size() != 2)
        throw InputError(spec.params.location(),
                         who + ": a " + spec.type + " joint connects exactly two bodies" +
                             (roles.empty() ? "" : ", " + roles) + ", got " + std::to_string(spec.bodies.size()));
}

// A joint whose rows are SPH / DOT1 / DOT2 primitives between the marker frames
// (i = marker 0, j = marker 1). Subclasses add coordinates, relative motions or rows.
class PrimitiveJoint : public Joint {
public:
    explicit PrimitiveJoint(const JointSpec& spec) : mi_(spec.markers.at(0)), mj_(spec.markers.at(1)) {}

    // SPH between the marker origins: rows "x", "y", "z" (world components of d).
    void add_sph() {
        terms_.push_back({Kind::Sph, X, X});
        names_.insert(names_.end(), {"x", "y", "z"});
    }
    // DOT1(axis ai of marker i, axis aj of marker j).
    void add_dot1(Axis ai, Axis aj, std::string name) {
        terms_.push_back({Kind::Dot1, ai, aj});
        names_.push_back(std::move(name));
    }
    // DOT2(axis ai of marker i, d = r_P^i - r_P^j between the marker origins).
    void add_dot2(Axis ai, std::string name) {
        has_dot2_ = true;
        terms_.push_back({Kind::Dot2, ai, X});
        names_.push_back(std::move(name));
    }
    void set_relative_motion(std::optional<RelativeMotion> motion) { motion_ = std::move(motion); }

    int rows() const override { return static_cast<int>(names_.size()); }

    void evaluate(const BodyStates& bodies, ConstraintEval& out) const override {
        const Pair pair(bodies);
        int row = 0;
        for (const Term& t : terms_) {
            switch (t.kind) {
            case Kind::Sph:
                write(out, row, sph(pair, mi_.u_bar, mj_.u_bar));
                row += 3;
                break;
            case Kind::Dot1:
                write(out, row++, dot1(pair, mi_.A_bar.col(t.ai), mj_.A_bar.col(t.aj)));
                break;
            case Kind::Dot2:
                write(out, row++, dot2(pair, mi_.A_bar.col(t.ai), mi_.u_bar, mj_.u_bar));
                break;
            }
        }
    }

    // The primitives' gamma derivative (above). A subclass with rows of its own goes without (the
    // caller differentiates gamma); one that changes the primitive rows' gamma must say false.
    bool has_gamma_velocity_transpose() const override { return rows() == primitive_rows(); }
    void gamma_velocity_transpose(const BodyStates& bodies, const double* weights, double* out) const override {
        const Pair pair(bodies);
        const Grad12 grad(out);
        int row = 0;
        for (const Term& t : terms_) {
            switch (t.kind) {
            case Kind::Sph:
                sph_gamma_gradient(pair, mi_.u_bar, mj_.u_bar, Vec3(weights[row], weights[row + 1], weights[row + 2]), grad);
                row += 3;
                break;
            case Kind::Dot1:
                dot1_gamma_gradient(pair, mi_.A_bar.col(t.ai), mj_.A_bar.col(t.aj), weights[row++], grad);
                break;
            case Kind::Dot2:
                dot2_gamma_gradient(pair, mi_.A_bar.col(t.ai), mi_.u_bar, mj_.u_bar, weights[row++], grad);
                break;
            }
        }
    }

    std::string row_name(int row) const override {
        return row >= 0 && row < static_cast<int>(names_.size()) ? names_[row] : Joint::row_name(row);
    }

    std::optional<RelativeMotion> relative_motion() const override { return motion_; }

    // SPH and DOT1 rows have gammas of the angular velocities alone (Eqs. 7.166, 7.170); DOT2's
    // holds d-dot, hence the Rdots. A subclass with rows or a coordinate of its own depends,
    // unless it says otherwise (SpatialRevolute: its angle is an atan2 of two DOT1s).
    bool gamma_depends_on_translation() const override {
        return has_dot2_ || rows() != primitive_rows() || has_coordinate();
    }

protected:
    const Marker& marker_i() const { return mi_; }
    const Marker& marker_j() const { return mj_; }
    // Row count of the primitive rows (subclasses append their own after these).
    int primitive_rows() const { return static_cast<int>(names_.size()); }

private:
    enum class Kind { Sph, Dot1, Dot2 };
    struct Term {
        Kind kind;
        int ai, aj;  // marker axis indices
    };
    Marker mi_, mj_;
    std::vector<Term> terms_;
    bool has_dot2_ = false;
    std::vector<std::string> names_;
    std::optional<RelativeMotion> motion_;
};

// Relative motions (axes in the joint frame of body i).
// A joint of primitives between the two markers of a spatial pair (checked as by
// require_spatial_pair); the caller adds its rows and relative motion.
inline std::unique_ptr<PrimitiveJoint> primitive_joint(const JointSpec& spec, const std::string& planar_hint) {
    require_spatial_pair(spec, planar_hint);
    return std::make_unique<PrimitiveJoint>(spec);
}

using mbd::prismatic_along;  // (joint.hpp) for the joints that use this namespace
using mbd::revolute_about;

}  // namespace spatial
}  // namespace mbd
