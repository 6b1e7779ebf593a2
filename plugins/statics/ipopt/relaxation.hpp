// The search for a STABLE equilibrium (default objective, see docs/statics.md): the path of
// the over-damped motion
//     D dq/dtau = Q(q) - J^T lambda,     C(q) = 0
// (no inertia, a diagonal damping metric D) leaves unstable equilibria and ends at a stable
// one. It is followed by pseudo-transient continuation (Kelley and Keyes, "Convergence
// analysis of pseudo-transient continuation", SIAM J. Numer. Anal. 35:508-523, 1998):
// linearly implicit Euler steps in the pseudo-time tau,
//     (D / dtau + K) dx + J^T dlambda = R,    J dx = -C,
// with K = -dQ/dq + d(J^T lambda)/dq the tangent stiffness (book Eq. 6.171 linearised) and
// R = Q - J^T lambda, lambda the least-squares multipliers. A small dtau is a gradient-flow
// step along the forces; dtau grows as the residual falls (switched evolution relaxation:
// dtau *= |R_old| / |R_new|) and the iteration becomes Newton's method near the
// equilibrium. Unlike Newton from the start, it needs no regular Jacobian there (a pendulum
// held horizontal by nothing: dQ/dq singular) and it does not stop at an unstable
// equilibrium: a start that already is one is displaced along the tangent direction of
// negative stiffness first. Steps are limited to 0.1 of the increment units (rotations in
// rad, translations in units of the model's size), so the path is not skipped.
//
// The constraints by a null-space method, which tolerates redundant rows: dx = -J^+ C + Z u,
// Z an orthonormal basis of ker J (SVD). Dense: meant for nv <= 600.
#pragma once

#include "dense_decompositions.hpp"
#include "evaluator.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace mbd::ipopt_plugin {

struct RelaxationResult {
    bool converged = false;
    Eigen::VectorXd q;    // the configuration reached
    int iterations = 0;
    int displacements = 0;  // moves off an unstable equilibrium
};

class Relaxation {
public:
    // unit: per velocity component, the size of a unit increment (1 rad for rotations, the
    // model's length for translations); stability_tolerance as StaticsOptions.
    Relaxation(System& sys, Evaluator& ev, Eigen::VectorXd unit, double stability_tolerance)
        : sys_(sys), ev_(ev), unit_(std::move(unit)), stability_tolerance_(stability_tolerance),
          nv_(sys.nv()), mc_(sys.constraint_rows(true)) {}

    RelaxationResult run(const Eigen::VectorXd& from, int max_iterations = 500) {
        RelaxationResult out;
        out.q = from;
        double dtau = 0.0, previous = -1.0, d0 = 0.0;
        for (int it = 0; it < max_iterations; ++it) {
            out.iterations = it;
            evaluate(out.q);
            const double r = R_.size() ? R_.cwiseAbs().maxCoeff() : 0.0;
            const double c = C_.size() ? C_.cwiseAbs().maxCoeff() : 0.0;
            const double q_scale = 1.0 + (Q_.size() ? Q_.cwiseAbs().maxCoeff() : 0.0);
            stiffness(out.q);
            if (r <= 1e-9 * q_scale && c <= constraint_tolerance()) {
                // an equilibrium: stable (done) or unstable (move off it along its unstable direction)
                Eigen::VectorXd direction;
                if (out.displacements >= 3 || !unstable_direction(direction)) {
                    out.converged = true;
                    return out;
                }
                const double size = scaled_size(direction);
                sys_.advance_positions(out.q, (0.05 / size) * direction);
                ++out.displacements;
                dtau = 0.0;
                previous = -1.0;
                continue;
            }
            if (dtau == 0.0) {
                // damping metric D = d0 diag(1 / unit^2) (N m per rad^2 for rotations) and a first
                // pseudo-time step that moves 0.01 units along the forces
                d0 = 0.0;
                for (int i = 0; i < nv_; ++i) d0 = std::max(d0, std::abs(K_(i, i)) * unit_[i] * unit_[i]);
                d0 = std::max(d0, 1e-12 * q_scale);
                double flow = 0.0;
                for (int i = 0; i < nv_; ++i) flow = std::max(flow, std::abs(R_[i]) * unit_[i] / d0);
                dtau = flow > 0.0 ? 0.01 / flow : 1.0;
            } else if (previous > 0.0) {
                dtau *= std::clamp(previous / r, 0.1, 10.0);  // switched evolution relaxation
            }
            previous = r;
            Eigen::VectorXd dx;
            if (!step(d0, dtau, dx)) return out;
            const double size = scaled_size(dx);
            if (size > 0.1) {
                dx *= 0.1 / size;  // stay on the path
                dtau *= 0.5;
            }
            sys_.advance_positions(out.q, dx);
        }
        return out;
    }

private:
    double constraint_tolerance() const { return 1e-10 * std::max(1.0, unit_.maxCoeff()); }

    double scaled_size(const Eigen::VectorXd& x) const {
        double m = 0.0;
        for (int i = 0; i < nv_; ++i) m = std::max(m, std::abs(x[i]) / unit_[i]);
        return m;
    }

    // C, J, Q, lambda (least squares from J^T lambda = Q), R = Q - J^T lambda, Z, J^+ at q
    void evaluate(const Eigen::VectorXd& q) {
        const State s = ev_.state(q);
        sys_.generalized_forces(s, Q_);
        if (mc_ == 0) {
            C_.resize(0);
            lambda_.resize(0);
            R_ = Q_;
            Z_ = Eigen::MatrixXd::Identity(nv_, nv_);
            return;
        }
        ConstraintValues cv;
        sys_.constraints(s, cv, true);
        C_ = cv.C;
        J_ = Eigen::MatrixXd(cv.J);
        svd_ = singular_value_decomposition(J_, true, 1e-10);
        rank_ = svd_.rank;
        Z_ = svd_.V.rightCols(nv_ - rank_);
        // lambda = (J^T)^+ Q = U_r S_r^-1 V_r^T Q
        const Eigen::VectorXd w = svd_.V.leftCols(rank_).transpose() * Q_;
        lambda_ = svd_.U.leftCols(rank_) * w.cwiseQuotient(svd_.values.head(rank_));
        R_ = Q_ - J_.transpose() * lambda_;
    }

    // K = -dQ/dq + d(J^T lambda)/dq at q (velocity coordinates), symmetrised
    void stiffness(const Eigen::VectorXd& q) {
        ev_.clear_blocks();
        ev_.add_force_jacobian(q, -1.0);
        if (mc_ > 0) ev_.add_constraint_curvature(q, lambda_, Eigen::VectorXd(), 1.0);
        K_ = ev_.dense_blocks();
        K_ = 0.5 * (K_ + K_.transpose()).eval();
    }

    // The tangent direction of most negative stiffness, if its eigenvalue is below -tol.
    bool unstable_direction(Eigen::VectorXd& direction) const {
        if (Z_.cols() == 0) return false;
        const Eigen::MatrixXd H = Z_.transpose() * K_ * Z_;
        Eigen::VectorXd values;
        Eigen::MatrixXd vectors;
        const double tol = stability_tolerance_ * std::max(1.0, K_.cwiseAbs().maxCoeff());
        if (!symmetric_eigen(H, values, &vectors) || values[0] >= -tol) return false;
        direction = Z_ * vectors.col(0);
        return true;
    }

    // One pseudo-time step: dx = -J^+ C + Z u, Z^T (D/dtau + K) Z u = Z^T (R - (D/dtau + K) dx_p).
    bool step(double d0, double dtau, Eigen::VectorXd& dx) const {
        Eigen::MatrixXd A = K_;
        for (int i = 0; i < nv_; ++i) A(i, i) += d0 / (unit_[i] * unit_[i] * dtau);
        Eigen::VectorXd dx_p = Eigen::VectorXd::Zero(nv_);
        if (mc_ > 0 && rank_ > 0) {
            const Eigen::VectorXd w = svd_.U.leftCols(rank_).transpose() * C_;
            dx_p = -svd_.V.leftCols(rank_) * w.cwiseQuotient(svd_.values.head(rank_));
        }
        dx = dx_p;
        if (Z_.cols() > 0) {
            const Eigen::MatrixXd H = Z_.transpose() * A * Z_;
            const Eigen::VectorXd b = Z_.transpose() * (R_ - A * dx_p);
            const Eigen::VectorXd u = H.fullPivLu().solve(b);
            dx += Z_ * u;
        }
        return dx.allFinite();
    }

    System& sys_;
    Evaluator& ev_;
    Eigen::VectorXd unit_;
    double stability_tolerance_;
    int nv_, mc_, rank_ = 0;
    Eigen::VectorXd C_, Q_, lambda_, R_;
    Eigen::MatrixXd J_, Z_, K_;
    SingularValueDecomposition svd_;
};

}  // namespace mbd::ipopt_plugin
