// The index-3 problem: the equations of motion as the index-3 DAE
//
//     M vdot + J(q)^T lambda = Q(t, q, v),     C(q, t) = 0
//
// that an implicit integrator of that DAE (generalized-alpha, Arnold & Bruls 2007) solves
// at each step. A formulation that can be integrated this way provides one
// (Formulation::index3_problem()); the integrator asks it for everything it needs, the
// residuals, the iteration matrix and the projection after a step, and never reaches around
// it to the System. The integrator keeps the method: its time discretisation (which state
// an iterate of vdot stands for), the scaling of the rows, the linear algebra and the Newton
// iteration.
//
// One evaluate() per iterate; the other calls read what it computed:
//   residual:          r = M vdot + J^T lambda - Q,  and  C  (constraint_values().C)
//   iteration matrix:  [ M - gamma' dQ/dv - beta' (dQ/dq - d(J^T lambda)/dq)   J^T ]
//                      [ J                                                     0   ]
//                      the derivative of (r, C / beta') with respect to (vdot, lambda)
//                      when q and v follow vdot as  dq/dvdot = beta' I,  dv/dvdot = gamma' I
//                      (the constraint rows scaled by 1/beta', Bottasso, Bauchau & Cardona
//                      2007, so the matrix stays well conditioned as h -> 0);
//                      beta' = gamma' = 0 gives the saddle-point matrix of the consistent
//                      accelerations [M J^T; J 0] [vdot; lambda] = [Q; gamma].
// The constraint rows are the joints' rows, then the drivers' (System layout); the DAE has
// no velocity-level (nonholonomic) rows.
//
// SystemIndex3Problem is the problem of a System whose ODE state y holds q and v in some
// form the formulation converts (the augmented formulation's y = [q; v]).
#pragma once

#include <mbd/kit/formulation.hpp>
#include <mbd/kit/singularity.hpp>
#include <mbd/kit/system.hpp>

#include <Eigen/Core>
#include <Eigen/Sparse>

#include <algorithm>
#include <string>
#include <vector>

namespace mbd {

class MBD_SDK_API Index3Problem {
public:
    using Triplets = std::vector<Eigen::Triplet<double>>;
    virtual ~Index3Problem() = default;

    // --- sizes; the integrator's state is the formulation's ODE state y
    virtual int velocity_count() const = 0;    // nv: rows of M, of r and of vdot
    virtual int constraint_count() const = 0;  // nc: rows of C and of lambda
    virtual void state_from_y(double t, const Eigen::VectorXd& y, State& state) = 0;
    virtual void y_from_state(const State& state, Eigen::VectorXd& y) = 0;

    // --- positions
    // q <- q (+) dv: a position increment in velocity coordinates (System::advance_positions).
    virtual void advance_positions(Eigen::VectorXd& q, const Eigen::VectorXd& dv) const = 0;
    // The projection the formulation wants on the positions of each accepted step (unit
    // Euler parameters); C itself is held by the iteration.
    virtual void project_positions(Eigen::VectorXd& q) const = 0;

    // --- the equations at an iterate
    virtual const Eigen::SparseMatrix<double>& mass_matrix() const = 0;  // constant
    // Q, C, J and gamma at `state`, for the calls below until the next evaluate().
    virtual void evaluate(const State& state) = 0;
    virtual const Eigen::VectorXd& forces() const = 0;  // Q
    virtual const ConstraintValues& constraint_values() const = 0;  // C, J, gamma
    // r = M vdot + J^T lambda - Q.
    virtual void residual(const Eigen::VectorXd& vdot, const Eigen::VectorXd& lambda, Eigen::VectorXd& r) const = 0;
    // The iteration matrix (header) at the evaluated state as (nv + nc) x (nv + nc) triplets
    // appended to `out` (entries at one place are to be summed). `lambda`: the multipliers of
    // the geometric stiffness d(J^T lambda)/dq, or null to leave that term out (it only
    // changes Newton's rate).
    virtual void iteration_matrix(double beta_p, double gamma_p, const Eigen::VectorXd* lambda, Triplets& out) = 0;

    // --- diagnostics
    // The rank of J at the evaluated state becomes the reference (the start of a run).
    virtual void set_reference_rank(double t) = 0;
    // Throws DynamicsError naming the rows when J at the evaluated state lost rank since.
    virtual void check_rank(double t) = 0;
    // "joint 'O' (x)" or "driver 'motor'": constraint row `row`, for messages.
    virtual std::string describe_row(int row) const = 0;
};

// The index-3 problem of a System, its ODE state converted by a formulation. Bound to the
// System in the formulation's bind(); before that, only whether a formulation has one.
class SystemIndex3Problem final : public Index3Problem {
public:
    explicit SystemIndex3Problem(Formulation& formulation) : formulation_(formulation) {}

    void bind(System& system) {
        system_ = &system;
        jt_lambda_.resize(system.nv());
        jt_lambda_fd_.resize(system.nv());
        unit_.resize(system.nv());
    }

    int velocity_count() const override { return system_->nv(); }
    int constraint_count() const override { return system_->constraint_rows(true); }
    void state_from_y(double t, const Eigen::VectorXd& y, State& state) override { formulation_.from_ode(t, y, state); }
    void y_from_state(const State& state, Eigen::VectorXd& y) override { formulation_.to_ode(state, y); }

    void advance_positions(Eigen::VectorXd& q, const Eigen::VectorXd& dv) const override {
        system_->advance_positions(q, dv);
    }
    void project_positions(Eigen::VectorXd& q) const override { system_->normalize(q); }

    const Eigen::SparseMatrix<double>& mass_matrix() const override { return system_->mass_matrix(); }
    void evaluate(const State& state) override {
        state_ = &state;
        system_->generalized_forces(state, Q_);
        system_->constraints(state, cv_, true);
    }
    const Eigen::VectorXd& forces() const override { return Q_; }
    const ConstraintValues& constraint_values() const override { return cv_; }
    void residual(const Eigen::VectorXd& vdot, const Eigen::VectorXd& lambda, Eigen::VectorXd& r) const override {
        r.noalias() = system_->mass_matrix() * vdot;
        r -= Q_;
        if (lambda.size() > 0) r.noalias() += cv_.J.transpose() * lambda;
    }

    void iteration_matrix(double beta_p, double gamma_p, const Eigen::VectorXd* lambda, Triplets& out) override {
        const int nv = system_->nv();
        system_->force_jacobians(*state_, dQ_dq_, dQ_dv_);
        append(out, system_->mass_matrix(), 1.0);
        if (gamma_p != 0.0) append(out, dQ_dv_, -gamma_p);
        if (beta_p != 0.0) append(out, dQ_dq_, -beta_p);
        const Eigen::SparseMatrix<double>& J = cv_.J;
        for (int k = 0; k < J.outerSize(); ++k)
            for (Eigen::SparseMatrix<double>::InnerIterator it(J, k); it; ++it) {
                out.emplace_back(nv + it.row(), it.col(), it.value());
                out.emplace_back(it.col(), nv + it.row(), it.value());
            }
        if (lambda && lambda->size() > 0) {
            geometric_stiffness(*lambda);
            for (int c = 0; c < nv; ++c)
                for (int r = 0; r < nv; ++r) out.emplace_back(r, c, beta_p * geometric_(r, c));
        }
    }

    void set_reference_rank(double t) override {
        singularity_.reset();
        if (cv_.J.rows() > 0) singularity_.check(*system_, t, cv_.J);
    }
    void check_rank(double t) override {
        if (cv_.J.rows() > 0) singularity_.check(*system_, t, cv_.J);
    }
    std::string describe_row(int row) const override { return system_->describe_row(row); }

private:
    static void append(Triplets& out, const Eigen::SparseMatrix<double>& A, double s) {
        for (int k = 0; k < A.outerSize(); ++k)
            for (Eigen::SparseMatrix<double>::InnerIterator it(A, k); it; ++it)
                out.emplace_back(it.row(), it.col(), s * it.value());
    }
    // d(J^T lambda)/dq at the evaluated state by forward differences, column by column.
    void geometric_stiffness(const Eigen::VectorXd& lambda) {
        const int nv = system_->nv();
        geometric_.resize(nv, nv);
        jt_lambda_.noalias() = cv_.J.transpose() * lambda;
        const State& state = *state_;
        const double eps = 1e-7 * std::max(1.0, state.q.lpNorm<Eigen::Infinity>());
        for (int j = 0; j < nv; ++j) {
            state_fd_.t = state.t;
            state_fd_.q = state.q;
            state_fd_.v = state.v;
            unit_.setZero();
            unit_[j] = eps;
            system_->advance_positions(state_fd_.q, unit_);
            system_->constraints(state_fd_, cv_fd_, true);
            jt_lambda_fd_.noalias() = cv_fd_.J.transpose() * lambda;
            geometric_.col(j) = (jt_lambda_fd_ - jt_lambda_) / eps;
        }
    }

    Formulation& formulation_;
    System* system_ = nullptr;
    const State* state_ = nullptr;  // the evaluated state (the integrator's, alive until the next evaluate)
    Eigen::VectorXd Q_;
    ConstraintValues cv_;
    Eigen::SparseMatrix<double> dQ_dq_, dQ_dv_;
    // the geometric stiffness's differences
    Eigen::MatrixXd geometric_;
    State state_fd_;
    ConstraintValues cv_fd_;
    Eigen::VectorXd jt_lambda_, jt_lambda_fd_, unit_;
    SingularityMonitor singularity_;  // J's rank at the start, asked again when Newton fails
};

}  // namespace mbd
