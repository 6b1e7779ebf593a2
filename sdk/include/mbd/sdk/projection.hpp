// Coordinate projection onto the constraint manifold in the kinetic-energy metric,
// shared by the formulations that integrate y = [q; v] (augmented, amalgamated).
// Header-only, over the SDK's System.
//
// Positions: Newton-Raphson on C(q, t) = 0 with steps of least kinetic-energy norm,
//     dq = -M^-1 J^T S^-1 C,    S = J M^-1 J^T
// (the minimum-norm Newton of book Eqs. 3.111-3.117 in the M metric; positions advanced
// with System::advance_positions, so Euler parameters stay unit), to `tolerance` on
// max |C|, and always at least one Newton step when C != 0; then velocities
// v <- v - M^-1 J^T S^-1 (J v + C_t), so that book Eq. 6.138 (J v + C_t = 0) holds.
// Why at least one step: a projection that leaves violations below the tolerance alone is
// not a smooth map of the state; inside a multistep integrator (CVODE's CVodeSetProjFn) its
// corrections, switching on and off at the size of the tolerance, are noise in the BDF
// history that no smaller step reduces, and at tight tolerances CVODE stopped with "the
// error test failed repeatedly or with |h| = hmin". One Newton step from a violation at the
// tolerance leaves round-off (issue 20; docs/integrators.md).
//
// The linear algebra is the caller's: `factor(robust)` factors S at cv.J (robust: a
// rank-revealing / damped path for (nearly) redundant rows), `solve_S(x)` overwrites x
// with S^-1 x, `apply_Minv(x, out)` sets out = M^-1 x. The projection is tried with the
// fast factorization first and, if Newton does not converge, once more with the robust
// one. DenseMetricSolver below is a ready-made dense implementation.
#pragma once

#include <mbd/sdk/system.hpp>

#include <Eigen/Dense>

#include <cmath>
#include <utility>

namespace mbd {

// Scratch of project_onto_constraints, for a caller that must not allocate per projection.
struct ProjectionWorkspace {
    Eigen::VectorXd x, tmp, dv;
};

// Projects (q0, v0) at time t; on success returns true with the result in state.
// cv is scratch (left at the projected state), and so is ws.
template <class Factor, class SolveS, class ApplyMinv>
bool project_onto_constraints(System& system, double t, const Eigen::VectorXd& q0, const Eigen::VectorXd& v0,
                              double tolerance, State& state, ConstraintValues& cv, Factor&& factor, SolveS&& solve_S,
                              ApplyMinv&& apply_Minv, ProjectionWorkspace& ws) {
    Eigen::VectorXd &x = ws.x, &tmp = ws.tmp, &dv = ws.dv;
    tmp.resize(system.nv());
    dv.resize(system.nv());
    for (int attempt = 0; attempt < 2; ++attempt) {
        const bool robust = attempt > 0;
        state.t = t;
        state.q = q0;
        state.v = v0;
        system.normalize(state.q);
        bool converged = false;
        for (int iteration = 0; iteration < 25; ++iteration) {
            system.constraints(state, cv, true);
            const double violation = cv.C.size() ? cv.C.template lpNorm<Eigen::Infinity>() : 0.0;
            if (!std::isfinite(violation)) break;
            // at least one Newton step whenever C != 0 (see the header)
            if (violation == 0.0 || (iteration > 0 && violation <= tolerance)) {
                converged = true;
                break;
            }
            factor(robust);
            x = cv.C;
            solve_S(x);
            tmp.noalias() = cv.J.transpose() * x;
            apply_Minv(tmp, dv);
            dv = -dv;
            if (!dv.allFinite()) break;
            system.advance_positions(state.q, dv);
            if (dv.template lpNorm<Eigen::Infinity>() <= 1e-3 * tolerance) {
                system.constraints(state, cv, true);
                converged = cv.C.template lpNorm<Eigen::Infinity>() <= 1e3 * tolerance;
                break;
            }
        }
        if (!converged) continue;
        factor(robust);
        x.noalias() = cv.J * state.v;
        x += cv.C_t;
        solve_S(x);
        tmp.noalias() = cv.J.transpose() * x;
        apply_Minv(tmp, dv);
        state.v -= dv;
        if (!state.q.allFinite() || !state.v.allFinite()) continue;
        return true;
    }
    return false;
}

template <class Factor, class SolveS, class ApplyMinv>
bool project_onto_constraints(System& system, double t, const Eigen::VectorXd& q0, const Eigen::VectorXd& v0,
                              double tolerance, State& state, ConstraintValues& cv, Factor&& factor, SolveS&& solve_S,
                              ApplyMinv&& apply_Minv) {
    ProjectionWorkspace ws;
    return project_onto_constraints(system, t, q0, v0, tolerance, state, cv, factor, solve_S, apply_Minv, ws);
}

// A dense S = J M^-1 J^T solver for project_onto_constraints: LDL^T with pivoting, and,
// for a (near) rank-deficient S (redundant constraints) or when asked to be robust, the
// minimum-norm solution S^+ = (W^T)^+ W^+ with W = J Lm (M^-1 = Lm Lm^T) from complete
// orthogonal decompositions (singular values below 1e-10 of the largest are zero).
class DenseMetricSolver {
public:
    void bind(System& system) {
        const Eigen::MatrixXd M(system.mass_matrix());
        Minv_ = M.inverse();
        Minv_ = 0.5 * (Minv_ + Minv_.transpose());
        Lm_ = Eigen::LLT<Eigen::MatrixXd>(Minv_).matrixL();
    }
    void apply_Minv(const Eigen::VectorXd& x, Eigen::VectorXd& out) const { out.noalias() = Minv_ * x; }
    void factor(const Eigen::SparseMatrix<double>& J, bool robust) {
        // S = J M^-1 J^T from the sparse J, into storage kept from call to call (dense
        // products this size would pack their blocks in fresh heap buffers)
        JMinv_.noalias() = J * Minv_;
        S_.noalias() = J * JMinv_.transpose();
        pseudo_ = false;
        if (S_.rows() == 0) return;
        ldlt_.compute(S_);
        const auto& D = ldlt_.vectorD();
        const double dmax = D.cwiseAbs().maxCoeff();
        if (robust || ldlt_.info() != Eigen::Success || !(dmax > 0) || D.minCoeff() <= 1e-8 * dmax) {
            W_.noalias() = J * Lm_;
            cod_w_.setThreshold(1e-10);
            cod_wt_.setThreshold(1e-10);
            cod_w_.compute(W_);
            cod_wt_.compute(W_.transpose());
            pseudo_ = true;
        }
    }
    void solve(Eigen::VectorXd& x) {
        if (x.size() == 0) return;
        if (pseudo_) {
            pseudo_solve(cod_w_, x, w_);
            pseudo_solve(cod_wt_, w_, x);
        } else {
            x = ldlt_.solve(x);
        }
    }

private:
    // x = A^+ b from the COD of A, as Eigen's CompleteOrthogonalDecomposition::solve computes
    // it (A P = Q [T 0; 0 0] Z) but in this solver's storage: Eigen's solve allocates its
    // temporaries at every call. b and x are distinct.
    void pseudo_solve(const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>& cod, const Eigen::VectorXd& b,
                      Eigen::VectorXd& x) {
        const Eigen::Index rank = cod.rank(), rows = cod.rows(), cols = cod.cols();
        const Eigen::MatrixXd& QTZ = cod.matrixQTZ();
        y_.setZero(cols);
        if (rank > 0) {
            c_ = b;  // c = Q^T b: the reflectors H_0 ... H_{rank-1}, in that order
            for (Eigen::Index k = 0; k < rank; ++k)
                reflect(c_.segment(k, rows - k), QTZ.col(k).tail(rows - k - 1), cod.hCoeffs()(k));
            y_.head(rank) = c_.head(rank);  // T z = c (upper triangular, rank x rank)
            QTZ.topLeftCorner(rank, rank).triangularView<Eigen::Upper>().solveInPlace(y_.head(rank));
            for (Eigen::Index k = 0; k < rank && rank < cols; ++k) {  // y = Z^T [z; 0]
                if (k != rank - 1) std::swap(y_[k], y_[rank - 1]);
                reflect(y_.segment(rank - 1, cols - rank + 1), QTZ.row(k).tail(cols - rank).transpose(),
                        cod.zCoeffs()(k));
                if (k != rank - 1) std::swap(y_[k], y_[rank - 1]);
            }
        }
        x.noalias() = cod.colsPermutation() * y_;  // undo the column pivoting
    }
    // s <- (I - tau v v^T) s with v = [1; essential], in the order of Eigen's
    // applyHouseholderOnTheLeft
    template <class Segment, class Essential>
    static void reflect(Segment&& s, const Essential& essential, double tau) {
        if (s.size() == 1) {
            s[0] *= 1.0 - tau;
            return;
        }
        if (tau == 0.0) return;
        double w = essential.dot(s.tail(s.size() - 1));
        w += s[0];
        s[0] -= tau * w;
        for (Eigen::Index i = 1; i < s.size(); ++i) s[i] -= (tau * essential[i - 1]) * w;
    }

    Eigen::MatrixXd Minv_, Lm_, JMinv_, W_, S_;
    Eigen::VectorXd w_, c_, y_;  // pseudo_solve's storage
    Eigen::LDLT<Eigen::MatrixXd> ldlt_;
    Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod_w_, cod_wt_;
    bool pseudo_ = false;
};

}  // namespace mbd
