// Planar constraint primitives: the building blocks of the planar joints.
//
// Bodies are planar (q = [x, y, theta], v = qdot, book Sec. 3.5); body k of a
// joint owns the Jacobian columns 3k .. 3k+2 in the joint's body order. Every
// primitive here is scleronomic (C_t = 0) and ADDS its contribution
//     C,   J (= dC/dq),   gamma (= Q_d, with Cddot = J qddot - gamma, book Eq. 3.124)
// into rows of a RowSink, so that primitives can be combined in one row (gear,
// rack and pinion) and reused for joint coordinates. Start a joint evaluation
// with `clear(out)` (or `clear(coordinate, ...)`) and add primitives into it.
//
// The formulas hold at any state (not only on the constraint manifold): every
// gamma is the exact velocity remainder of Cddot, derived with
//   d/dt (A v_bar) = omega A_theta v_bar,   d2/dt2 (A v_bar) = alpha A_theta v_bar - omega^2 A v_bar
// (book Eqs. 3.29, 3.42-3.43).
#pragma once

#include <mbd/sdk/body_state.hpp>
#include <mbd/sdk/joint.hpp>

#include <Eigen/Core>

#include <cassert>
#include <cmath>
#include <memory>
#include <string>

namespace mbd {
namespace planar {

constexpr int kCols = 3;  // velocities per planar body

// Column of the first velocity (xdot) of body k in a joint's Jacobian.
constexpr int body_col(int k) { return kCols * k; }

// Unit vector of angle phi in the axes it is measured in.
inline Vec2 unit(double phi) { return Vec2(std::cos(phi), std::sin(phi)); }

// A marker's x axis and y axis (the perpendicular h_bar of book Eq. 3.94) in body axes.
inline Vec2 marker_x(const Marker& m) { return unit(m.angle); }
inline Vec2 marker_y(const Marker& m) { return perp(unit(m.angle)); }

// Where primitives write: rows of a ConstraintEval, or the single row of a
// CoordinateEval (which has no C_t: time terms are dropped there; coordinates
// are never time dependent). Holds raw pointers: do not resize the target
// while a sink on it is alive.
class RowSink {
public:
    RowSink(ConstraintEval& out)  // NOLINT(google-explicit-constructor): a sink *is* its rows
        : C_(out.C.data()), C_t_(out.C_t.data()), gamma_(out.gamma.data()), J_(out.J.data()),
          ld_(static_cast<int>(out.J.outerStride())), rows_(static_cast<int>(out.C.size())),
          cols_(static_cast<int>(out.J.cols())) {
        assert(out.J.rows() == out.C.size() && out.C_t.size() == out.C.size() &&
               out.gamma.size() == out.C.size());
    }
    RowSink(CoordinateEval& s)  // NOLINT(google-explicit-constructor)
        : C_(&s.value), C_t_(nullptr), gamma_(&s.gamma), J_(s.J.data()), ld_(1), rows_(1),
          cols_(static_cast<int>(s.J.size())) {}

    int rows() const { return rows_; }
    int cols() const { return cols_; }
    double& C(int r) { return C_[check_row(r)]; }
    double& gamma(int r) { return gamma_[check_row(r)]; }
    void add_C_t(int r, double v) {
        check_row(r);
        if (C_t_) C_t_[r] += v;
    }
    double& J(int r, int c) {
        assert(c >= 0 && c < cols_);
        return J_[check_row(r) + static_cast<long>(c) * ld_];
    }
    // Add a 1x2 block to the translational columns (x, y) of body k.
    void add_J_R(int r, int k, const Vec2& row) {
        J(r, body_col(k)) += row.x();
        J(r, body_col(k) + 1) += row.y();
    }
    void add_J_theta(int r, int k, double value) { J(r, body_col(k) + 2) += value; }

private:
    int check_row(int r) const {
        assert(r >= 0 && r < rows_);
        return r;
    }
    double* C_;
    double* C_t_;
    double* gamma_;
    double* J_;
    int ld_;
    int rows_;
    int cols_;
};

// Zero a joint's output before adding primitives into it.
inline void clear(ConstraintEval& out) {
    out.C.setZero();
    out.J.setZero();
    out.C_t.setZero();
    out.gamma.setZero();
}
// Size and zero a coordinate's output for `nbodies` planar bodies.
inline void clear(CoordinateEval& s, int nbodies, bool periodic) {
    s.value = 0.0;
    s.gamma = 0.0;
    s.J.setZero(kCols * nbodies);
    s.periodic = periodic;
}

// Factory-side validation shared by the planar joints: a planar spec with `min_bodies` to
// `max_bodies` bodies and, when `markers`, a marker for each. Throws InputError naming the joint.
inline void check_spec(const JointSpec& spec, int min_bodies, int max_bodies, bool markers) {
    const std::string who = spec.type + " '" + spec.name + "'";
    if (spec.dimension != Dimension::Planar)
        throw InputError(spec.params.location(), who + " is built as a planar joint, but the scene is spatial");
    const int n = static_cast<int>(spec.bodies.size());
    if (n < min_bodies || n > max_bodies) {
        const std::string want = min_bodies == max_bodies
                                     ? std::to_string(min_bodies)
                                     : std::to_string(min_bodies) + " or " + std::to_string(max_bodies);
        throw InputError(spec.params.location(),
                         who + " connects " + want + " bodies, got " + std::to_string(n));
    }
    if (markers && static_cast<int>(spec.markers.size()) != n)
        throw InputError(spec.params.location(), who + " needs a joint frame on each of its " +
                                                     std::to_string(n) + " bodies, got " +
                                                     std::to_string(spec.markers.size()));
}

// Factory-side validation of a planar contact element (gear_pair, rack_pinion): a
// planar scene (`spatial_note` says what a spatial one lacks), check_spec with 2 to
// `max_bodies` bodies, and two different bodies in contact (the error: "TYPE 'NAME'
// <verb> body 'B' <preposition> itself"). Returns "TYPE 'NAME'" for the caller's errors.
inline std::string check_contact_spec(const JointSpec& spec, int max_bodies, bool markers,
                                      const std::string& spatial_note, const std::string& verb,
                                      const std::string& preposition) {
    const std::string who = spec.type + " '" + spec.name + "'";
    if (spec.dimension != Dimension::Planar)
        throw InputError(spec.params.location(), who + " is a planar joint; " + spatial_note);
    check_spec(spec, 2, max_bodies, markers);
    if (spec.bodies[0].name == spec.bodies[1].name)
        throw InputError(spec.params.location(),
                         who + " " + verb + " body '" + spec.bodies[0].name + "' " + preposition + " itself");
    return who;
}

// Initial relative angle of the joint frames on bodies i and j (spec order), from the initial
// body angles and the marker angles: (theta0^j + phi_j) - (theta0^i + phi_i). Not wrapped, so a
// relative_angle row with this c is exactly zero in the initial configuration.
inline double initial_relative_angle(const JointSpec& spec, int i = 0, int j = 1) {
    return (spec.bodies[j].angle + spec.markers[j].angle) - (spec.bodies[i].angle + spec.markers[i].angle);
}

// A two-body planar joint between the joint frames mi, mj that holds their relative
// angle at c, its initial value (fixed, prismatic); make_frame_pair_joint builds one.
class FramePairJoint : public Joint {
public:
    FramePairJoint(const Marker& mi, const Marker& mj, double c) : mi_(mi), mj_(mj), c_(c) {}

protected:
    Marker mi_, mj_;
    double c_;
};
template <class J>
std::unique_ptr<Joint> make_frame_pair_joint(const JointSpec& spec) {
    check_spec(spec, 2, 2, true);
    return std::make_unique<J>(spec.markers[0], spec.markers[1], initial_relative_angle(spec));
}

// ---------------------------------------------------------------------------
// Point coincidence, rows r and r+1 (book Eqs. 3.129-3.133, revolute joint):
//   C = r_P^i - r_P^j = R^i + A^i u_bar^i - R^j - A^j u_bar^j
//   J = [ I | A_theta^i u_bar^i | -I | -A_theta^j u_bar^j ]            (3.130)
//   gamma = (thetadot^i)^2 A^i u_bar^i - (thetadot^j)^2 A^j u_bar^j       (3.133)
inline void point_coincidence(const BodyStates& b, int i, const Vec2& u_bar_i, int j,
                              const Vec2& u_bar_j, RowSink out, int r, double weight = 1.0) {
    const PlanarBody& bi = b.planar(i);
    const PlanarBody& bj = b.planar(j);
    const Vec2 ui = bi.A * u_bar_i, uj = bj.A * u_bar_j;
    const Vec2 C = bi.R + ui - bj.R - uj;
    const Vec2 ti = bi.A_theta * u_bar_i, tj = bj.A_theta * u_bar_j;
    const Vec2 gamma = bi.omega * bi.omega * ui - bj.omega * bj.omega * uj;
    for (int a = 0; a < 2; ++a) {
        out.C(r + a) += weight * C[a];
        out.gamma(r + a) += weight * gamma[a];
        out.J(r + a, body_col(i) + a) += weight;
        out.add_J_theta(r + a, i, weight * ti[a]);
        out.J(r + a, body_col(j) + a) -= weight;
        out.add_J_theta(r + a, j, -weight * tj[a]);
    }
}

// (d gamma / d v)^T w of point_coincidence's two rows (weights w[0], w[1]), added to out over the
// joint's columns: gamma = omega_i^2 A_i u_i - omega_j^2 A_j u_j depends on the angular velocities
// alone, d gamma / d omega_i = 2 omega_i A_i u_i (Eq. 3.133 differentiated).
inline void point_coincidence_gamma_gradient(const BodyStates& b, int i, const Vec2& u_bar_i, int j,
                                             const Vec2& u_bar_j, const double* w, double* out) {
    const PlanarBody& bi = b.planar(i);
    const PlanarBody& bj = b.planar(j);
    const Vec2 weights(w[0], w[1]);
    out[body_col(i) + 2] += 2.0 * bi.omega * weights.dot(bi.A * u_bar_i);
    out[body_col(j) + 2] -= 2.0 * bj.omega * weights.dot(bj.A * u_bar_j);
}

// Relative angle, row r (book Eq. 3.80 / first row of Eq. 3.94):
//   C = (theta^j + phi_j) - (theta^i + phi_i) - c,   J = [0 0 -1 | 0 0 1],   gamma = 0.
inline void relative_angle(const BodyStates& b, int i, double phi_i, int j, double phi_j, double c,
                           RowSink out, int r, double weight = 1.0) {
    out.C(r) += weight * ((b.planar(j).theta + phi_j) - (b.planar(i).theta + phi_i) - c);
    out.add_J_theta(r, i, -weight);
    out.add_J_theta(r, j, weight);
}

// A body angle measured from its initial value, row r (the terms of book Eqs. 3.104-3.105):
//   C = weight * (theta^k - theta0),   J = weight in column theta^k,   gamma = 0.
inline void body_angle(const BodyStates& b, int k, double theta0, RowSink out, int r,
                       double weight = 1.0) {
    out.C(r) += weight * (b.planar(k).theta - theta0);
    out.add_J_theta(r, k, weight);
}

// Offset of P^j from P^i projected on a direction v = A^i v_bar fixed in body i, row r:
//   C = v^T d,   d = r_P^j - r_P^i = R^j + A^j u_bar^j - R^i - A^i u_bar^i
//   J = [ -v^T | (A_theta^i v_bar)^T d - v^T A_theta^i u_bar^i | v^T | v^T A_theta^j u_bar^j ]
//   Cddot = vddot^T d + 2 vdot^T ddot + v^T dddot, with vdot = w_i A_theta^i v_bar,
//   vddot = a_i A_theta^i v_bar - w_i^2 v, so
//   gamma = w_i^2 v^T d - 2 vdot^T ddot + v^T (w_j^2 A^j u_bar^j - w_i^2 A^i u_bar^i).
// This is the book's dot-product constraint (Eq. 3.94, Ex. 3.14) in the direction i -> j; its
// gamma is the digest's corrected Q_d2 (book L4429 has a spurious term).
inline void projected_offset(const BodyStates& b, int i, const Vec2& v_bar, const Vec2& u_bar_i,
                             int j, const Vec2& u_bar_j, RowSink out, int r, double weight = 1.0) {
    const PlanarBody& bi = b.planar(i);
    const PlanarBody& bj = b.planar(j);
    const Vec2 v = bi.A * v_bar;
    const Vec2 v_th = bi.A_theta * v_bar;
    const Vec2 ui = bi.A * u_bar_i, uj = bj.A * u_bar_j;
    const Vec2 ti = bi.A_theta * u_bar_i, tj = bj.A_theta * u_bar_j;
    const Vec2 d = bj.R + uj - bi.R - ui;
    const Vec2 d_dot = bj.Rdot + bj.omega * tj - bi.Rdot - bi.omega * ti;
    const Vec2 v_dot = bi.omega * v_th;
    const double wi2 = bi.omega * bi.omega, wj2 = bj.omega * bj.omega;

    out.C(r) += weight * v.dot(d);
    out.add_J_R(r, i, -weight * v);
    out.add_J_theta(r, i, weight * (v_th.dot(d) - v.dot(ti)));
    out.add_J_R(r, j, weight * v);
    out.add_J_theta(r, j, weight * v.dot(tj));
    out.gamma(r) += weight * (wi2 * v.dot(d) - 2.0 * v_dot.dot(d_dot) + v.dot(wj2 * uj - wi2 * ui));
}

// Perpendicular distance, row r (book Eq. 3.94, prismatic joint, with the corrected Q_d2):
//   C = h^{iT} r_P^{ij},   h^i = A^i h_bar^i,   r_P^{ij} = r_P^i - r_P^j
// with h_bar^i the y axis of marker i (perpendicular to the sliding axis, marker i's x axis)
// and P^i, P^j the marker origins. Book sign (i - j): the negative of projected_offset.
inline void perpendicular_distance(const BodyStates& b, int i, const Marker& mi, int j,
                                   const Marker& mj, RowSink out, int r, double weight = 1.0) {
    projected_offset(b, i, marker_y(mi), mi.u_bar2(), j, mj.u_bar2(), out, r, -weight);
}

// Offset of P^j from P^i projected on a FIXED world direction n, row r (rack and pinion,
// book Ex. 3.9 with a moving pinion centre):
//   C = n^T (r_P^j - r_P^i),   J = [ -n^T | -n^T A_theta^i u_bar^i | n^T | n^T A_theta^j u_bar^j ],
//   gamma = n^T (w_j^2 A^j u_bar^j - w_i^2 A^i u_bar^i).
inline void world_offset(const BodyStates& b, const Vec2& n, int i, const Vec2& u_bar_i, int j,
                         const Vec2& u_bar_j, RowSink out, int r, double weight = 1.0) {
    const PlanarBody& bi = b.planar(i);
    const PlanarBody& bj = b.planar(j);
    const Vec2 ui = bi.A * u_bar_i, uj = bj.A * u_bar_j;
    out.C(r) += weight * n.dot(bj.R + uj - bi.R - ui);
    out.add_J_R(r, i, -weight * n);
    out.add_J_theta(r, i, -weight * n.dot(bi.A_theta * u_bar_i));
    out.add_J_R(r, j, weight * n);
    out.add_J_theta(r, j, weight * n.dot(bj.A_theta * u_bar_j));
    out.gamma(r) += weight * n.dot(bj.omega * bj.omega * uj - bi.omega * bi.omega * ui);
}

// A constant added to row r (constants of integration, initial values).
inline void constant(double value, RowSink out, int r) { out.C(r) += value; }

// ---------------------------------------------------------------------------
// Joint coordinates (architecture.md, "Joint coordinates"), written into a CoordinateEval
// sized for `nbodies` bodies.

// s = theta^j - theta^i (book Eq. 3.80), not periodic.
inline void relative_angle_coordinate(const BodyStates& b, int i, int j, CoordinateEval& s) {
    clear(s, b.size(), false);
    relative_angle(b, i, 0.0, j, 0.0, 0.0, s, 0);
}

// s = axis_i . (R^j - r_P^i), axis_i = A^i (marker i x axis): travel of body j's mass centre
// along the axis from the joint point on body i.
inline void axial_travel_coordinate(const BodyStates& b, int i, const Marker& mi, int j,
                                    CoordinateEval& s) {
    clear(s, b.size(), false);
    projected_offset(b, i, marker_x(mi), mi.u_bar2(), j, Vec2::Zero(), s, 0);
}

}  // namespace planar
}  // namespace mbd
