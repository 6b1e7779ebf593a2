// The recursive path of the embedding formulation extended with cut joints (issue 13): a
// spanning tree in joint coordinates (articulated_body.hpp: y = [s; u], forward kinematics)
// plus loop-closure rows: the rows of the joints that are not tree edges (cut joints, joints
// without a supported relative motion) and of the drivers, evaluated by the System in
// absolute coordinates at the tree's forward-kinematics state and written in joint
// coordinates (book Sec. 4.5's embedding of the tree; Sec. 6.6's augmented method for the
// rows that remain):
//     v = H u,  vdot = H udot + a          (H = dv/du, a: vdot at udot = 0; tree recursion)
//     M_u = H^T M H,  h = H^T (Q - M a),  Phi_u = J_c H,  gamma_u = gamma_c - J_c a
//     [M_u Phi_u^T; Phi_u 0] [udot; lambda_c] = [h; gamma_u]      (Eq. 6.141 in joint space)
// (joint_space_saddle.hpp). Dense: meant for small looped or driven systems.
//
// Drift: the tree rows hold by construction; project() pulls s onto the closure rows by
// Newton with least-M_u-norm steps (ds = -M_u^-1 Phi_u^T S^-1 C_c, the kinetic-energy metric of
// the augmented projection, projection.hpp, restricted to the tree's motions), then
// u <- u - M_u^-1 Phi_u^T S^-1 (Phi_u u + C_t,c) (book Eq. 6.138 on the closure rows).
//
// Redundant closure rows (rank-deficient at the assembled initial state, e.g. the Bricard)
// are left out with multiplier 0 and named in the log, as the dense path drops them; a rank
// drop later is a singular configuration, caught by the embedding's rank test after each
// accepted step (singularity.hpp), meanwhile solved by the minimum-norm path.
//
// Multipliers of every System row: the closure rows' lambda_c from the solve; a tree joint's
// from the force its child's subtree needs, f_b = M_b vdot_b - Q_b + (J_c^T lambda_c)_b +
// sum_children Phi^T f_c (leaves to root), through its own rows (articulated_body.hpp).
#pragma once

#include "articulated_body.hpp"
#include "joint_space_saddle.hpp"

#include <vector>

namespace mbd::articulated {

class LoopClosure final : public ArticulatedBody {
public:
    void bind(System& system, const FormulationOptions& options) override;
    void rhs(double t, const Eigen::VectorXd& y, Eigen::VectorXd& ydot) override;
    bool project(double t, Eigen::VectorXd& y) override;
    void multipliers(const State& state, Eigen::VectorXd& lambda) override;
    void accelerations(const State& state, Eigen::VectorXd& vdot) override;
    // the least relative pivot of the last factorization of S (0 after the robust path)
    double least_relative_pivot() const { return saddle_.least_relative_pivot(); }
    // the System's J (joints and drivers) at the positions of the last successful project()
    const Eigen::SparseMatrix<double>& projected_jacobian() const { return cv_.J; }

private:
    // at the kinematics in bodies_: H_, a_ (System layout), the absolute state_, cv_ and the
    // closure rows in joint space (Phi_, gamma_u_, C_c_, Ct_c_)
    void joint_space(double t);
    // M_u_ = H^T M H and h_ = H^T (Q - M a) with Q_ set
    void joint_mass(bool with_h);
    // solves the saddle point for udot_ and lambda_c_ (Q_ and joint_space() done)
    void dynamics(double t);
    // the structurally redundant closure rows at the assembled initial state
    void find_redundant_rows(const FormulationOptions& options);
    // saddle_ at (M_u_, Phi_), re-selecting the left-out rows when the kept ones grow ill-conditioned
    bool factor(double t, bool robust);
    bool project_positions(double t, Eigen::VectorXd& s, bool robust);
    // s <- s (+) du: 1-DOF coordinates add, Euler parameters turn by du (body axes) and renormalise
    void advance(Eigen::VectorXd& s, const Eigen::VectorXd& du) const;
    // at a given state: kinematics, forces, dynamics (results in udot_, lambda_c_, bodies_)
    void solve_at(const State& state);
    [[noreturn]] void saddle_error(double t, const char* what) const;
    // throws the named singular configuration when the velocity correction du_ at u_ is no drift
    void check_no_jump(double t);
    static constexpr double kJumpRatio = 1e-2;

    std::vector<int> rows_;     // the System rows of the closure (joints' rows, then drivers')
    std::vector<int> row_of_;   // per System row: its closure index, -1 for a tree joint's row
    std::vector<int> dropped_;  // closure indices left out (redundant)
    std::vector<char> is_dropped_;
    MessageLog log_;
    double projection_tolerance_ = 1e-12;
    int newton_iterations_ = 25;
    Eigen::MatrixXd H6_;        // per body 6 rows: (Rdot, wbar) = H6 u + a6
    Eigen::MatrixXd H_, MH_, Mu_, Phi_;
    Eigen::VectorXd a6_, a_, work_, h_, gamma_u_, C_c_, Ct_c_, lambda_c_, r_, du_, vdot_, ytmp_;
    ConstraintValues cv_;
    JointSpaceSaddle saddle_;
};

}  // namespace mbd::articulated
