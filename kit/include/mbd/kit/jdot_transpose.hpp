// Jdot^T mu for a vector mu of constraint-row weights, in O(n) constraint evaluations' work
// (a fixed number of them, independent of the number of bodies), from gamma alone: the joints
// give J and gamma (Cddot = J vdot - gamma, book Eq. 3.124), not J's time derivative.
//
// gamma is quadratic in v: gamma(q, v) = G(v, v) (+ terms without v: C_tt of drivers), so
// D = d gamma / d v = 2 G(v, .) and, for any w, exactly (polarization)
//     D w = (gamma(q, v + w) - gamma(q, v - w)) / 2.
// With the body-axis angular velocities of spatial bodies (quasi-velocities) the time
// derivative of J v is not J-dot v alone: Jdot w = -D w / 2 + J Lambda(v) w / 2 with
// Lambda(v) w = omega_v x omega_w in each body's rotational components (the Lie bracket of the
// body-axis angular-velocity fields; the form the Hamiltonian formulation uses column by column,
// hamiltonian.cpp). Hence
//     Jdot^T mu = -D^T mu / 2 - (omega_v x (J^T mu)_rot) / 2      per body, Lambda^T = -[omega_v]x.
// D has J's pattern (a row of a joint depends on the velocities of the joint's bodies only), so
// it is found column group by column group (Curtis-Powell-Reid): the bodies are coloured so
// that no two bodies of a colour share a row, and one polarization with w = s (sum of the unit
// vectors of one velocity component of every body of a colour) gives, on each row, the entry of
// the one column of the group that the row holds. A chain needs 2 colours: 2 x 3 (planar) or
// 2 x 6 (spatial) groups, 2 constraint evaluations each, whatever its length. When every joint
// says that its gamma does not depend on the translational velocities (Joint::
// gamma_depends_on_translation: pins, ball joints), D's translational columns are zero and only
// the angular components are probed: 2 x 1 or 2 x 3 groups. A joint that gives D^T mu itself
// (Joint::has_gamma_velocity_transpose: pins, and the spatial joints of primitives) is not probed:
// its rows are summed in one pass (System::gamma_velocity_transpose), and the polarization covers
// the other joints and the drivers (none on a chain of pins or ball joints: no probe at all).
#pragma once

#include <mbd/kit/system.hpp>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <vector>

namespace mbd {

class JdotTranspose {
public:
    // the colouring of the System's bodies (by the rows they share)
    void bind(System& system);
    int groups() const { return colours_ * (nvb_ - first_component_); }

    // out = Jdot^T mu at state (t, q, v); J at that state (J does not depend on v)
    void apply(System& system, const State& state, const Eigen::SparseMatrix<double>& J, const Eigen::VectorXd& mu,
               Eigen::VectorXd& out);
    // out = Jdot w on every row by one polarization (two gamma evaluations), for a few directions w:
    // Jdot w = -(gamma(v + w) - gamma(v - w)) / 4 + J Lambda(v) w / 2 (see the top of this file)
    void times(System& system, const State& state, const Eigen::SparseMatrix<double>& J,
               const Eigen::Ref<const Eigen::VectorXd>& w, Eigen::VectorXd& out);

private:
    int nvb_ = 3, colours_ = 0;
    int first_component_ = 0;  // the first velocity component probed (past the translational ones when D has none)
    bool planar_ = true;
    bool analytic_ = false;  // some joint gives (d gamma / d v)^T mu itself (Joint::gamma_velocity_transpose)
    std::vector<std::vector<int>> bodies_of_colour_, rows_of_body_;
    State probe_;
    Eigen::VectorXd gamma_plus_, gamma_minus_, Jt_mu_;
};

}  // namespace mbd
