// Loads from joint reactions solved together with the multipliers: friction in a pin or a
// guide whose normal load is the joint's own reaction (Force::load_joint).
//
// The friction force of such an element is affine in its load N (Coulomb: F = mu N, a pin's
// moment mu r N + preload), Q = Q_0 + G N (G = dQ/dN, System::reaction_load_directions), and
// the multipliers of the saddle point (book Eq. 6.141) are linear in Q:
//     lambda(N) = lambda_0 + sum_g N_g L_g,   L_g = S^-1 J M^-1 G_g   (S = J M^-1 J^T),
// lambda_0 the multipliers of Q_0 (gamma included). The load is the magnitude of the joint's
// reaction force f on its body, transverse to the element's axis a (a pin's radial load, a
// guide's normal reaction): with P = I - a a^T,
//     N_k = | P_k (f_k(lambda_0) + sum_g N_g f_k(L_g)) |
// (f linear in lambda, Eq. 6.146). These K equations, one per element, are the algebraic loop
// between friction and reaction; they are solved by Newton's method at every evaluation, so
// the loop is exact (to round-off), not lagged a step. With a single element, N = |a + b N|
// has one solution when |b| < 1; |b| >= 1 is self-locking (the friction the reaction causes
// raises the reaction at least as much: a jammed wedge), and the solver stops with an error
// naming the element.
#pragma once

#include <mbd/kit/formulation.hpp>
#include <mbd/kit/system.hpp>
#include <mbd/sdk/text.hpp>

#include <Eigen/Dense>
#include <Eigen/Sparse>

#include <cmath>
#include <string>
#include <vector>

namespace mbd {

class ReactionLoadSolver {
public:
    void bind(System& system) {
        system_ = &system;
        count_ = static_cast<int>(system.reaction_loaded_forces().size());
        zero_.setZero(count_);
        N_.setZero(count_);
        body_.assign(count_, -1);
        for (int k = 0; k < count_; ++k) {
            const JointInfo& joint = system.joint(system.force(system.reaction_loaded_forces()[k]).load_joint);
            for (int b : joint.bodies)
                if (b >= 0 && body_[k] < 0) body_[k] = b;  // the reaction on the joint's first moving body
        }
    }
    bool active() const { return count_ > 0; }
    // Before the forces are evaluated: they are Q_0, at N = 0.
    void clear() {
        if (count_) system_->set_reaction_loads(zero_);
    }

    // Given Q = Q_0 and lambda = lambda_0 at `state` (cv: its constraint rows, as solved), and
    // `respond(dQ, dlambda)`: dlambda = S^-1 J M^-1 dQ with the formulation's factorization.
    // Adds G N to Q and sum N_g L_g to lambda, and sets the loads on the System.
    template <class Respond>
    void solve(double t, const State& state, const Eigen::SparseMatrix<double>& J, Eigen::VectorXd& Q,
               Eigen::VectorXd& lambda, const Respond& respond) {
        if (!count_) return;
        System& sys = *system_;
        sys.reaction_load_directions(state, G_, axes_);
        L_.resize(lambda.size(), count_);
        for (int g = 0; g < count_; ++g) {
            column_ = G_.col(g);
            respond(column_, response_);
            L_.col(g) = response_;
        }
        // a_k = P f_k(lambda_0), B_kg = P f_k(L_g)
        a_.resize(count_);
        B_.assign(count_ * count_, Vec3::Zero());
        for (int k = 0; k < count_; ++k) {
            a_[k] = transverse(k, J, lambda);
            for (int g = 0; g < count_; ++g) B_[k * count_ + g] = transverse(k, J, L_.col(g));
        }
        for (int k = 0; k < count_; ++k) N_[k] = a_[k].norm();  // the loads without the loop
        Eigen::MatrixXd jacobian(count_, count_);
        Eigen::VectorXd residual(count_);
        bool converged = false;
        for (int iteration = 0; iteration < 50 && !converged; ++iteration) {
            for (int k = 0; k < count_; ++k) {
                Vec3 f = a_[k];
                for (int g = 0; g < count_; ++g) f += N_[g] * B_[k * count_ + g];
                const double n = f.norm();
                residual[k] = N_[k] - n;
                for (int g = 0; g < count_; ++g)
                    jacobian(k, g) = (k == g ? 1.0 : 0.0) - (n > 0.0 ? f.dot(B_[k * count_ + g]) / n : 0.0);
            }
            const Eigen::VectorXd step = jacobian.fullPivLu().solve(residual);
            if (!step.allFinite()) break;
            N_ -= step;
            converged = step.lpNorm<Eigen::Infinity>() <= 1e-14 * (1.0 + N_.lpNorm<Eigen::Infinity>());
        }
        int worst = -1;
        for (int k = 0; k < count_; ++k)
            if (!(N_[k] >= 0.0) || !std::isfinite(N_[k])) worst = k;
        if (!converged || worst >= 0) {
            const int k = worst >= 0 ? worst : 0;
            const ForceInfo& force = sys.force(sys.reaction_loaded_forces()[k]);
            throw DynamicsError(t, "t = " + format_time(t) + ": force '" + force.name +
                                       "': its load from the reaction of joint '" + sys.joint(force.load_joint).name +
                                       "' has no solution: the friction locks the joint (the friction the reaction "
                                       "causes raises the reaction as much again); lower the friction coefficient "
                                       "or the pin radius");
        }
        Q.noalias() += G_ * N_;
        lambda.noalias() += L_ * N_;
        sys.set_reaction_loads(N_);
    }

private:
    // The reaction force of element k's joint on its body, -J^T lambda over the joint's rows
    // (Eq. 6.146; translational columns: world axes), with the part along the element's axis removed.
    template <class Multipliers>
    Vec3 transverse(int k, const Eigen::SparseMatrix<double>& J, const Multipliers& lambda) const {
        System& sys = *system_;
        const JointInfo& joint = sys.joint(sys.force(sys.reaction_loaded_forces()[k]).load_joint);
        const bool planar = sys.dimension() == Dimension::Planar;
        const int nvb = velocities_per_body(sys.dimension());
        const int velocity_first = sys.constraint_rows(true) + joint.velocity_row_offset;
        const bool velocity_rows = J.rows() >= sys.constraint_rows(true) + sys.velocity_constraint_rows();
        Vec3 f = Vec3::Zero();
        for (int c = 0; c < (planar ? 2 : 3); ++c) {
            for (Eigen::SparseMatrix<double>::InnerIterator it(J, body_[k] * nvb + c); it; ++it) {
                const int row = static_cast<int>(it.row());
                const bool own = (row >= joint.first_row && row < joint.first_row + joint.rows) ||
                                 (velocity_rows && row >= velocity_first && row < velocity_first + joint.velocity_rows);
                if (own) f[c] -= it.value() * lambda[row];
            }
        }
        const Vec3& axis = axes_[k];
        return f - axis.dot(f) * axis;
    }

    System* system_ = nullptr;
    int count_ = 0;
    std::vector<int> body_;
    Eigen::VectorXd zero_, N_, column_, response_;
    Eigen::MatrixXd G_, L_;
    std::vector<Vec3> axes_, a_, B_;
};

}  // namespace mbd
