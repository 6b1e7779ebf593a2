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

#include <mbd/kit/partition.hpp>
#include <mbd/kit/system.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <vector>

namespace mbd {

// Scratch of the functions below, owned by the caller and reused from call to call: once it
// has seen a partition of a given rank, they allocate nothing (the rank does not change
// for the life of a System; a re-selection keeps it).
struct VelocityTransformWorkspace {
    Eigen::MatrixXd Jd, Ji, Bd;               // J_d = J[rows, d], J_i = J[rows, i], -B_d
    Eigen::PartialPivLU<Eigen::MatrixXd> lu;  // of J_d (or J_d^T)
    Eigen::VectorXd b, x, dv;
    PartitionWorkspace elimination;           // dependent_pivot_ratio
    CoordinatePartition pivots;
};

// out = A[rows, cols], out = x[rows], and y[rows] = x: explicit loops, because Eigen's
// indexed views copy a std::vector of indices (a heap allocation per view).
inline void gather(const Eigen::MatrixXd& A, const std::vector<int>& rows, const std::vector<int>& cols,
                   Eigen::MatrixXd& out) {
    out.resize(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(cols.size()));
    for (size_t j = 0; j < cols.size(); ++j)
        for (size_t i = 0; i < rows.size(); ++i) out(i, j) = A(rows[i], cols[j]);
}
inline void gather(const Eigen::VectorXd& x, const std::vector<int>& rows, Eigen::VectorXd& out) {
    out.resize(static_cast<Eigen::Index>(rows.size()));
    for (size_t i = 0; i < rows.size(); ++i) out[i] = x[rows[i]];
}
inline void scatter(const Eigen::VectorXd& x, const std::vector<int>& rows, Eigen::VectorXd& y) {
    for (size_t i = 0; i < rows.size(); ++i) y[rows[i]] = x[i];
}

// max |x[rows]|; NaN when one of them is NaN
inline double max_abs(const Eigen::VectorXd& x, const std::vector<int>& rows) {
    double m = 0.0;
    for (int r : rows) {
        const double a = std::abs(x[r]);
        if (std::isnan(a)) return a;
        m = std::max(m, a);
    }
    return m;
}

// Smallest / largest pivot of J_d's complete-pivoting LU (0 when J_d is singular):
// the re-selection test of Sec. 6.12.
inline double dependent_pivot_ratio(const Eigen::MatrixXd& J, const CoordinatePartition& p,
                                    VelocityTransformWorkspace& ws) {
    if (p.rank == 0) return 1.0;
    gather(J, p.rows, p.dependent, ws.elimination.a);
    partition_workspace_matrix(1.0, 0.0, {}, ws.elimination, ws.pivots);
    return ws.pivots.rank < p.rank ? 0.0 : ws.pivots.pivot_ratio;
}

// B (n_v x k) and gamma' (n_v) from J and gamma (Eqs. 6.80-6.94). Returns false when
// J_d is singular (non-finite results).
inline bool velocity_transform(const Eigen::MatrixXd& J, const Eigen::VectorXd& gamma, const CoordinatePartition& p,
                               Eigen::MatrixXd& B, Eigen::VectorXd& gamma_prime, VelocityTransformWorkspace& ws) {
    const int nv = static_cast<int>(J.cols());
    const int k = static_cast<int>(p.independent.size());
    B.setZero(nv, k);
    gamma_prime.setZero(nv);
    for (int c = 0; c < k; ++c) B(p.independent[c], c) = 1.0;
    if (p.rank == 0) return true;
    gather(J, p.rows, p.dependent, ws.Jd);
    ws.lu.compute(ws.Jd);
    gather(gamma, p.rows, ws.b);
    ws.x = ws.lu.solve(ws.b);  // gamma'_d
    if (!ws.x.allFinite()) return false;
    if (k > 0) {  // a fully driven (0-DOF) system has no B columns (Eigen may not solve for none)
        gather(J, p.rows, p.independent, ws.Ji);
        // -B_d, one column at a time: a solve with a matrix right-hand side packs its blocks in
        // heap buffers once they exceed Eigen's stack limit (J_d of a few hundred rows)
        ws.Bd.resize(p.rank, k);
        for (int c = 0; c < k; ++c) ws.Bd.col(c) = ws.lu.solve(ws.Ji.col(c));
        if (!ws.Bd.allFinite()) return false;
        for (int c = 0; c < k; ++c)
            for (int i = 0; i < p.rank; ++i) B(p.dependent[i], c) = -ws.Bd(i, c);
    }
    scatter(ws.x, p.dependent, gamma_prime);
    return true;
}

// The full velocity v from the independent components (Eq. 6.169):
// J_d v_d = -(J_i v_i + C_t) on the kept rows.
inline void dependent_velocities(const Eigen::MatrixXd& J, const Eigen::VectorXd& C_t, const CoordinatePartition& p,
                                 const Eigen::VectorXd& vi, Eigen::VectorXd& v, VelocityTransformWorkspace& ws) {
    v.setZero(J.cols());
    scatter(vi, p.independent, v);
    if (p.rank == 0) return;
    gather(C_t, p.rows, ws.b);
    ws.b = -ws.b;
    if (!p.independent.empty()) {
        gather(J, p.rows, p.independent, ws.Ji);
        ws.b.noalias() -= ws.Ji * vi;
    }
    gather(J, p.rows, p.dependent, ws.Jd);
    ws.lu.compute(ws.Jd);
    ws.x = ws.lu.solve(ws.b);
    scatter(ws.x, p.dependent, v);
}

// Multipliers from J^T lambda = r (r = Q - M vdot = -Q_c, book Eq. 6.128): its dependent
// rows J_d^T lambda_kept = r_d determine lambda; redundant rows get zero.
inline void multipliers_from_dependent_rows(const Eigen::MatrixXd& J, const CoordinatePartition& p,
                                            const Eigen::VectorXd& r, Eigen::VectorXd& lambda,
                                            VelocityTransformWorkspace& ws) {
    lambda.setZero(J.rows());
    if (p.rank == 0) return;
    gather(J, p.rows, p.dependent, ws.Jd);
    ws.lu.compute(ws.Jd.transpose());
    gather(r, p.dependent, ws.b);
    ws.x = ws.lu.solve(ws.b);
    scatter(ws.x, p.rows, lambda);
}

// Dependent positions by Newton-Raphson holding the independent directions:
// J_d dd = -C (kept rows), q <- q (+) P_d dd (book Sec. 6.12 step 3; Ch. 3 Eq. 3.117),
// until max |C| on the kept rows <= tolerance. state.q is updated; returns false if
// the iteration did not converge; cv is left at the final q. The rows are those of
// System::constraints_with_velocity_rows (the partition's): a velocity-level row has C = 0, so
// in a Newton step it only keeps A dd = 0 (the correction does not move a no-slip contact
// along its surface); without such rows they are the rows of System::constraints. The linear algebra is the
// caller's: step(cv, dv) sets dv (size n_v, zero at the independent components) to the
// Newton step J_d dv_d = -C[rows] at cv and returns false when it is not finite.
template <class NewtonStep>
bool correct_dependent_positions_with(System& system, State& state, const CoordinatePartition& p, double tolerance,
                                      int iterations, ConstraintValues& cv, Eigen::VectorXd& dv, NewtonStep&& step) {
    bool converged = p.rank == 0;
    dv.resize(system.nv());
    for (int iteration = 0; iteration < iterations && !converged; ++iteration) {
        system.constraints_with_velocity_rows(state, cv, true);
        const double violation = max_abs(cv.C, p.rows);
        if (!std::isfinite(violation)) break;
        // at least one Newton step whenever C != 0, so that the correction is a smooth map of the
        // state (inside a multistep integrator, corrections that switch on and off at the
        // tolerance are noise in its history: see projection.hpp)
        if (violation == 0.0 || (iteration > 0 && violation <= tolerance)) {
            converged = true;
            break;
        }
        dv.setZero();
        if (!step(cv, dv)) break;
        system.advance_positions(state.q, dv);
    }
    system.constraints_with_velocity_rows(state, cv, true);
    return converged;
}

// The same with a dense LU of J_d; J is left at the final q.
inline bool correct_dependent_positions(System& system, State& state, const CoordinatePartition& p,
                                        double tolerance, int iterations, ConstraintValues& cv, Eigen::MatrixXd& J,
                                        VelocityTransformWorkspace& ws) {
    const bool converged = correct_dependent_positions_with(
        system, state, p, tolerance, iterations, cv, ws.dv, [&](const ConstraintValues& at, Eigen::VectorXd& dv) {
            J = at.J;
            gather(J, p.rows, p.dependent, ws.Jd);
            ws.lu.compute(ws.Jd);
            gather(at.C, p.rows, ws.b);
            ws.b = -ws.b;
            ws.x = ws.lu.solve(ws.b);
            if (!ws.x.allFinite()) return false;
            scatter(ws.x, p.dependent, dv);
            return true;
        });
    J = cv.J;
    return converged;
}

}  // namespace mbd
