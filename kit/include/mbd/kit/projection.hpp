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
// The joints' velocity-level rows (A v = b, System::constraints_with_velocity_rows) take part
// with their C = 0: the velocity step projects onto them too; in a position step they add
// A dq = 0, so the correction of the holonomic rows does not move the no-slip points along
// the surface, and the positions they leave free stay free (their C is never nonzero).
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

#include <mbd/kit/dense_gram.hpp>
#include <mbd/kit/system.hpp>

#include <Eigen/Dense>

#include <cmath>
#include <vector>

namespace mbd {

// The projection's own vectors, kept by the caller so that projecting allocates nothing.
struct ProjectionScratch {
    Eigen::VectorXd q0, v0;   // the state to project (copied in by the caller)
    Eigen::VectorXd x, tmp, dv;
    void resize(int nq, int nv, int rows) {
        q0.setZero(nq);
        v0.setZero(nv);
        x.setZero(rows);
        tmp.setZero(nv);
        dv.setZero(nv);
    }
};

// Projects (work.q0, work.v0) at time t; on success returns true with the result in state.
// cv is scratch (left at the projected state).
template <class Factor, class SolveS, class ApplyMinv>
bool project_onto_constraints(System& system, double t, ProjectionScratch& work, double tolerance, State& state,
                              ConstraintValues& cv, Factor&& factor, SolveS&& solve_S, ApplyMinv&& apply_Minv) {
    const Eigen::VectorXd &q0 = work.q0, &v0 = work.v0;
    Eigen::VectorXd &x = work.x, &tmp = work.tmp, &dv = work.dv;
    for (int attempt = 0; attempt < 2; ++attempt) {
        const bool robust = attempt > 0;
        state.t = t;
        state.q = q0;
        state.v = v0;
        system.normalize(state.q);
        bool converged = false;
        for (int iteration = 0; iteration < 25; ++iteration) {
            system.constraints_with_velocity_rows(state, cv, true);
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
                system.constraints_with_velocity_rows(state, cv, true);
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

// A dense S = J M^-1 J^T solver for project_onto_constraints (dense_gram.hpp: S formed by
// body blocks; M^-1 applied body by body).
class DenseMetricSolver {
public:
    void bind(System& system) {
        mass_inverse_.bind(system, "coordinate projection");
        gram_.resize(system.constraint_rows(true) + system.velocity_constraint_rows(), system.nv());
    }
    void apply_Minv(const Eigen::VectorXd& x, Eigen::VectorXd& out) const { mass_inverse_.apply(x, out); }
    void factor(const Eigen::SparseMatrix<double>& J, bool robust) {
        if (robust || gram_.factor(J, mass_inverse_) <= 1e-8) gram_.factor_pseudo_inverse(J, mass_inverse_);
    }
    void solve(Eigen::VectorXd& x) { gram_.solve(x); }
    // for the singular-configuration screen (singularity.hpp): the last factorization's least
    // relative pivot (0 after the robust path) and the metric's distortion sqrt(cond M)
    double least_relative_pivot() const { return gram_.least_relative_pivot(); }
    double metric_distortion() const { return mass_inverse_.distortion(); }

private:
    BlockMassInverse mass_inverse_;
    DenseGram gram_;
};

}  // namespace mbd
