// The velocity transformation of the embedding technique on a coordinate partition
// (Shabana, Computational Dynamics, Sec. 6.5, Eqs. 6.79-6.99; Sec. 6.12), header-only so
// that every formulation that needs it (embedding's dense path, amalgamated,
// hamiltonian) builds B, gamma' and the dependent positions the same way.
//
// With a partition of J (partition.hpp: kept rows, dependent columns d, independent
// columns i; J_d = J[rows, d] nonsingular):
//   velocities   v = B v_i + c,    c_d = -J_d^-1 C_t, c_i = 0          (Eq. 6.169)
//   B            B_i = I, B_d = -J_d^-1 J_i                            (Eqs. 6.80-6.85)
//   gamma'       vdot = B vdot_i + gamma', gamma'_d = J_d^-1 gamma     (Eqs. 6.90-6.94)
// and the dependent positions follow from the independent ones by Newton-Raphson
// holding the independent directions, J_d dd = -C (book Sec. 6.12 step 3).
#pragma once

#include <mbd/sdk/partition.hpp>
#include <mbd/sdk/system.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <vector>

namespace mbd {

// Smallest / largest pivot of J_d's complete-pivoting LU (0 when J_d is singular):
// the re-selection test of Sec. 6.12.
inline double dependent_pivot_ratio(const Eigen::MatrixXd& J, const CoordinatePartition& p) {
    if (p.rank == 0) return 1.0;
    const Eigen::MatrixXd Jd = J(p.rows, p.dependent);
    const CoordinatePartition lu = partition_coordinates(Jd, 1.0, 0.0);
    return lu.rank < p.rank ? 0.0 : lu.pivot_ratio;
}

// B (n_v x k) and gamma' (n_v) from J and gamma (Eqs. 6.80-6.94). Returns false when
// J_d is singular (non-finite results).
inline bool velocity_transform(const Eigen::MatrixXd& J, const Eigen::VectorXd& gamma, const CoordinatePartition& p,
                               Eigen::MatrixXd& B, Eigen::VectorXd& gamma_prime) {
    const int nv = static_cast<int>(J.cols());
    const int k = static_cast<int>(p.independent.size());
    B.setZero(nv, k);
    gamma_prime.setZero(nv);
    for (int c = 0; c < k; ++c) B(p.independent[c], c) = 1.0;
    if (p.rank == 0) return true;
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(J(p.rows, p.dependent));
    const Eigen::VectorXd gd = lu.solve(Eigen::VectorXd(gamma(p.rows)));
    if (!gd.allFinite()) return false;
    if (k > 0) {  // a fully driven (0-DOF) system has no B columns (Eigen may not solve for none)
        const Eigen::MatrixXd Bd = -lu.solve(Eigen::MatrixXd(J(p.rows, p.independent)));
        if (!Bd.allFinite()) return false;
        B(p.dependent, Eigen::all) = Bd;
    }
    gamma_prime(p.dependent) = gd;
    return true;
}

// The full velocity v from the independent components (Eq. 6.169):
// J_d v_d = -(J_i v_i + C_t) on the kept rows.
inline void dependent_velocities(const Eigen::MatrixXd& J, const Eigen::VectorXd& C_t, const CoordinatePartition& p,
                                 const Eigen::VectorXd& vi, Eigen::VectorXd& v) {
    v.setZero(J.cols());
    for (size_t c = 0; c < p.independent.size(); ++c) v[p.independent[c]] = vi[c];
    if (p.rank == 0) return;
    Eigen::VectorXd b = -C_t(p.rows);
    if (!p.independent.empty()) b.noalias() -= J(p.rows, p.independent) * vi;
    const Eigen::VectorXd vd = J(p.rows, p.dependent).partialPivLu().solve(b);
    v(p.dependent) = vd;
}

// Multipliers from J^T lambda = r (r = Q - M vdot = -Q_c, book Eq. 6.128): its dependent
// rows J_d^T lambda_kept = r_d determine lambda; redundant rows get zero.
inline void multipliers_from_dependent_rows(const Eigen::MatrixXd& J, const CoordinatePartition& p,
                                            const Eigen::VectorXd& r, Eigen::VectorXd& lambda) {
    lambda.setZero(J.rows());
    if (p.rank == 0) return;
    const Eigen::MatrixXd JdT = J(p.rows, p.dependent).transpose();
    const Eigen::VectorXd lr = JdT.partialPivLu().solve(Eigen::VectorXd(r(p.dependent)));
    lambda(p.rows) = lr;
}

// Dependent positions by Newton-Raphson holding the independent directions:
// J_d dd = -C (kept rows), q <- q (+) P_d dd (book Sec. 6.12 step 3; Ch. 3 Eq. 3.117),
// until max |C| on the kept rows <= tolerance. state.q is updated; returns false if
// the iteration did not converge. cv and J are left at the final q.
inline bool correct_dependent_positions(System& system, State& state, const CoordinatePartition& p,
                                        double tolerance, int iterations, ConstraintValues& cv, Eigen::MatrixXd& J) {
    const int nv = system.nv();
    bool converged = p.rank == 0;
    Eigen::VectorXd dv(nv);
    for (int iteration = 0; iteration < iterations && !converged; ++iteration) {
        system.constraints(state, cv, true);
        J = Eigen::MatrixXd(cv.J);
        const double violation = cv.C(p.rows).lpNorm<Eigen::Infinity>();
        if (!std::isfinite(violation)) break;
        // at least one Newton step whenever C != 0, so that the correction is a smooth map of the
        // state (inside a multistep integrator, corrections that switch on and off at the
        // tolerance are noise in its history: see projection.hpp)
        if (violation == 0.0 || (iteration > 0 && violation <= tolerance)) {
            converged = true;
            break;
        }
        const Eigen::VectorXd dd = J(p.rows, p.dependent).partialPivLu().solve(Eigen::VectorXd(-cv.C(p.rows)));
        if (!dd.allFinite()) break;
        dv.setZero();
        dv(p.dependent) = dd;
        system.advance_positions(state.q, dv);
    }
    system.constraints(state, cv, true);
    J = Eigen::MatrixXd(cv.J);
    return converged;
}

}  // namespace mbd
