// The statics result: polish, angle wrapping, residual, diagnosis and stability (equilibrium.hpp).
#include "equilibrium.hpp"

#include "dense_decompositions.hpp"
#include "ipopt_common.hpp"

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace mbd::ipopt_plugin {
namespace {

// The verdict on the smallest eigenvalue (or pivot) of the stiffness, within +-tol of zero neutral.
std::string classify(double smallest, double tol) {
    if (smallest < -tol) return "unstable";
    if (smallest > tol) return "stable";
    return "neutral";
}

// The rows of the active constraints: J, then the gradients of the active limits.
std::vector<Eigen::Triplet<double>> active_rows(const ConstraintValues& cv, int mc,
                                              const std::vector<Coordinate>& rows) {
    std::vector<Eigen::Triplet<double>> t;
    if (mc > 0)
        for (int c = 0; c < cv.J.outerSize(); ++c)
            for (Eigen::SparseMatrix<double>::InnerIterator it(cv.J, c); it; ++it)
                t.emplace_back(it.row(), it.col(), it.value());
    for (size_t k = 0; k < rows.size(); ++k)
        for (const auto& e : rows[k].grad) t.emplace_back(mc + k, e.first, e.second);
    return t;
}

// Dense (nv <= 600): the eigenvalues of Z^T K Z, Z an orthonormal basis of ker A (SVD).
void dense_stability(const Eigen::MatrixXd& K_blocks, const Eigen::MatrixXd& A, double stability_tolerance,
                     StaticsResult& res) {
    const Eigen::Index nv = K_blocks.rows();
    const Eigen::MatrixXd K = 0.5 * (K_blocks + K_blocks.transpose());
    int rank = 0;
    const Eigen::MatrixXd Z = null_space(A, static_cast<int>(nv), rank, 1e-9);
    res.tangent_dimension = static_cast<int>(Z.cols());
    if (Z.cols() == 0) {
        res.stability = "stable";  // fully constrained: no motion possible
        res.tangent_eigenvalues.resize(0);
        return;
    }
    const Eigen::MatrixXd H = Z.transpose() * K * Z;
    symmetric_eigen(H, res.tangent_eigenvalues);
    const double scale = std::max(1.0, K.cwiseAbs().maxCoeff());
    res.stability = classify(res.tangent_eigenvalues.minCoeff(), stability_tolerance * scale);
}

// Large systems: inertia of K + rho A^T A (Finsler), sparse LDL^T.
void sparse_stability(const Eigen::SparseMatrix<double>& K_blocks, const Eigen::SparseMatrix<double>& A,
                      double stability_tolerance, StaticsResult& res) {
    Eigen::SparseMatrix<double> K = 0.5 * (Eigen::SparseMatrix<double>(K_blocks.transpose()) + K_blocks);
    double kmax = 1.0, amax = 1e-300;
    for (int c = 0; c < K.outerSize(); ++c)
        for (Eigen::SparseMatrix<double>::InnerIterator it(K, c); it; ++it) kmax = std::max(kmax, std::abs(it.value()));
    for (int c = 0; c < A.outerSize(); ++c)
        for (Eigen::SparseMatrix<double>::InnerIterator it(A, c); it; ++it) amax = std::max(amax, std::abs(it.value()));
    const double rho = 1e6 * kmax / (amax * amax);
    Eigen::SparseMatrix<double> P = K + rho * Eigen::SparseMatrix<double>(A.transpose() * A);
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(P);
    res.tangent_dimension = -1;
    if (ldlt.info() != Eigen::Success) {
        res.stability = "neutral";
        return;
    }
    const Eigen::VectorXd D = ldlt.vectorD();
    res.stability = classify(D.minCoeff(), stability_tolerance * kmax);
}

}  // namespace

void wrap_angles(System& sys, Evaluator& ev, const State& start, const StaticsOptions& opt, State& state) {
    const int nb = sys.body_count(), mc = sys.constraint_rows(true);
    Eigen::VectorXd q = state.q;
    for (int b = 0; b < nb; ++b) {
        if (sys.dimension() == Dimension::Planar) {
            const double a0 = start.q[3 * b + 2];
            q[3 * b + 2] = a0 + std::remainder(q[3 * b + 2] - a0, 2 * M_PI);
        } else if (q.segment<4>(7 * b + 3).dot(start.q.segment<4>(7 * b + 3)) < 0) {
            q.segment<4>(7 * b + 3) *= -1.0;
        }
    }
    if (q == state.q) return;
    if (mc > 0) {
        ConstraintValues a, b;
        State s = state;
        sys.constraints(s, a, true);
        s.q = q;
        sys.constraints(s, b, true);
        if ((a.C - b.C).cwiseAbs().maxCoeff() > 1e-9) return;
    }
    for (const JointLimit& l : opt.limits)
        if (std::abs(ev.coordinate(l.joint, q).value - ev.coordinate(l.joint, state.q).value) > 1e-9) return;
    state.q = q;
}

void polish(System& sys, Evaluator& ev, State& state, Eigen::VectorXd& lambda, Eigen::VectorXd& nu,
            const std::vector<JointLimit>& limits) {
    const int nv = sys.nv(), mc = sys.constraint_rows(true);
    std::vector<int> act;
    std::vector<double> bound;
    for (size_t k = 0; k < limits.size(); ++k) {
        const Coordinate c = ev.coordinate(limits[k].joint, state.q);
        const double gap = 1e-6 * (1.0 + std::abs(c.value));
        if (c.value - limits[k].lo < gap) { act.push_back(static_cast<int>(k)); bound.push_back(limits[k].lo); }
        else if (limits[k].hi - c.value < gap) { act.push_back(static_cast<int>(k)); bound.push_back(limits[k].hi); }
    }
    if (act.empty()) return;
    const int na = static_cast<int>(act.size()), n = nv + mc + na;
    for (int it = 0; it < 4; ++it) {
        ConstraintValues cv;
        if (mc > 0) sys.constraints(state, cv, true);
        Eigen::VectorXd Q;
        sys.generalized_forces(state, Q);
        Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n);
        Eigen::VectorXd F = Eigen::VectorXd::Zero(n);
        Eigen::VectorXd R = Q;
        if (mc > 0) {
            const Eigen::MatrixXd J(cv.J);
            A.block(0, 0, mc, nv) = J;
            A.block(mc + na, nv, nv, mc) = -J.transpose();
            F.head(mc) = cv.C;
            R -= J.transpose() * lambda;
        }
        for (int a = 0; a < na; ++a) {
            const Coordinate c = ev.coordinate(limits[act[a]].joint, state.q);
            F[mc + a] = c.value - bound[a];
            for (const auto& e : c.grad) {
                A(mc + a, e.first) += e.second;
                A(mc + na + e.first, nv + mc + a) -= e.second;
                R[e.first] -= e.second * nu[act[a]];
            }
        }
        F.tail(nv) = R;
        if (F.cwiseAbs().maxCoeff() < 1e-14 * (1.0 + Q.cwiseAbs().maxCoeff())) break;
        ev.clear_blocks();
        ev.add_force_jacobian(state.q, 1.0);
        ev.add_constraint_curvature(state.q, lambda, nu, -1.0);
        A.block(mc + na, 0, nv, nv) = ev.dense_blocks();
        const Eigen::VectorXd d = A.fullPivLu().solve(-F);
        if (!d.allFinite()) return;
        sys.advance_positions(state.q, d.head(nv));
        if (mc > 0) lambda += d.segment(nv, mc);
        for (int a = 0; a < na; ++a) nu[act[a]] += d[nv + mc + a];
    }
}

EquilibriumResidual measure_equilibrium(System& sys, Evaluator& ev, StaticsResult& res, const StaticsOptions& opt) {
    EquilibriumResidual out;
    const int nl = static_cast<int>(opt.limits.size());
    Eigen::VectorXd Q;
    sys.generalized_forces(res.state, Q);
    Eigen::VectorXd R = Q;
    if (sys.constraint_rows(true) > 0) {
        ConstraintValues cv;
        sys.constraints(res.state, cv, true);
        R -= cv.J.transpose() * res.lambda;
        out.c_max = cv.C.cwiseAbs().maxCoeff();
    }
    res.limit_active.assign(nl, false);
    for (int k = 0; k < nl; ++k) {
        const Coordinate c = ev.coordinate(opt.limits[k].joint, res.state.q);
        for (const auto& e : c.grad) R[e.first] -= e.second * res.limit_multipliers[k];
        out.bound_violation =
            std::max({out.bound_violation, opt.limits[k].lo - c.value, c.value - opt.limits[k].hi});
        const double scale = 1e-7 * (1.0 + std::abs(c.value));
        if (c.value - opt.limits[k].lo < scale || opt.limits[k].hi - c.value < scale) {
            res.limit_active[k] = true;
            out.active.push_back(k);
        }
    }
    out.r_max = R.size() ? R.cwiseAbs().maxCoeff() : 0.0;
    res.residual = std::max({out.c_max, out.r_max, out.bound_violation});
    out.q_scale = 1.0 + (Q.size() ? Q.cwiseAbs().maxCoeff() : 0.0);
    return out;
}

std::string failure_message(Ipopt::ApplicationReturnStatus status, const StaticsResult& res,
                            const EquilibriumResidual& r, double ctol, const std::string& callback_error) {
    std::ostringstream m;
    // Ipopt's "infeasible" covers the force balance too (virtual work: Q - J^T lambda = 0
    // is a constraint): with the joints, drivers and limits satisfied, it is the loads
    const bool geometry_holds = r.c_max <= ctol && r.bound_violation <= 0.0;
    if (status == Ipopt::Infeasible_Problem_Detected && geometry_holds)
        m << "no equilibrium exists under the applied loads: the joints, drivers and limits hold, but no "
             "configuration balances the forces (e.g. a constant torque or force that no joint, spring or "
             "limit can resist); check the loads, or add a spring, a driver or a limit that holds them "
             "(Ipopt: infeasible problem)";
    else if (status == Ipopt::Infeasible_Problem_Detected)
        m << "no configuration satisfies the joints, drivers and limits together (Ipopt: infeasible problem)";
    else if (!finished(status))
        m << "Ipopt failed (" << res.status << ") after " << res.iterations << " iterations";
    else
        m << "no equilibrium: Ipopt stopped with residual " << res.residual;
    m << "; max |C| = " << r.c_max << ", max |Q - J^T lambda| = " << r.r_max;
    if (r.bound_violation > 0) m << ", limit violation " << r.bound_violation;
    if (!callback_error.empty()) m << "; " << callback_error;
    return m.str();
}

void assess_stability(System& sys, Evaluator& ev, StaticsResult& res, const StaticsOptions& opt,
                      const std::vector<int>& active) {
    const int nv = sys.nv(), mc = sys.constraint_rows(true);
    ev.clear_blocks();
    ev.add_force_jacobian(res.state.q, -1.0);
    ev.add_constraint_curvature(res.state.q, res.lambda, res.limit_multipliers, 1.0);
    ConstraintValues cv;
    if (mc > 0) sys.constraints(res.state, cv, true);
    std::vector<Coordinate> rows;
    for (int k : active) rows.push_back(ev.coordinate(opt.limits[k].joint, res.state.q));
    const std::vector<Eigen::Triplet<double>> t = active_rows(cv, mc, rows);
    Eigen::SparseMatrix<double> A(mc + static_cast<int>(rows.size()), nv);
    A.setFromTriplets(t.begin(), t.end());
    if (nv <= 600)
        dense_stability(ev.dense_blocks(), Eigen::MatrixXd(A), opt.stability_tolerance, res);
    else
        sparse_stability(ev.sparse_blocks(), A, opt.stability_tolerance, res);
}

}  // namespace mbd::ipopt_plugin
