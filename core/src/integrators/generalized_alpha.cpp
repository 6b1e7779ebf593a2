// Generalized-alpha (Chung & Hulbert 1993) applied to the index-3 constrained
// equations of motion, in the form of Arnold & Bruls (2007), "Convergence of the
// generalized-alpha scheme for constrained mechanical systems", Multibody Syst.
// Dyn. 18:185-202:
//
//   M vdot_{n+1} + J(q_{n+1})^T lambda_{n+1} = Q(t_{n+1}, q_{n+1}, v_{n+1})
//   C(q_{n+1}, t_{n+1}) = 0
//   q_{n+1} = q_n (+) [h v_n + h^2 (1/2 - beta) a_n + h^2 beta a_{n+1}]
//   v_{n+1} = v_n + h (1 - gamma) a_n + h gamma a_{n+1}
//   (1 - alpha_m) a_{n+1} + alpha_m a_n = (1 - alpha_f) vdot_{n+1} + alpha_f vdot_n
//
// with alpha_m = (2 rho - 1)/(rho + 1), alpha_f = rho/(rho + 1),
// gamma = 1/2 + alpha_f - alpha_m, beta = (gamma + 1/2)^2 / 4 (rho = rho_infinity).
//
// The equations come from the formulation as its index-3 problem (kit index3_problem.hpp:
// the residuals, the iteration matrix below and the projection after a step); this file is
// the method: the discretisation, the scaling, the linear algebra and the Newton iteration.
//
// (+) is Index3Problem::advance_positions (System::advance_positions): planar bodies add the increment; spatial
// bodies add the translation and rotate the Euler parameters by the body-axis
// rotation vector through the exponential map. Because v = (Rdot, wbar) lives in
// the Lie algebra of R^3 x SO(3), this is the Lie-group generalized-alpha method
// of Brls, Cardona & Arnold (2012) with the tangent operator T(h dq) replaced by
// the identity in the iteration matrix only (the residual uses the exact map), so
// the approximation slows Newton slightly for large rotations per step but does
// not change the converged solution.
//
// Newton on (vdot_{n+1}, lambda_{n+1}) with the iteration matrix
//   [ M - gamma' dQ/dv - beta' dQ/dq    J^T ]     beta'  = h^2 beta (1 - alpha_f)/(1 - alpha_m)
//   [ J                                  0  ]     gamma' = h gamma (1 - alpha_f)/(1 - alpha_m)
// where the constraint rows are scaled by 1/beta' (Bottasso, Bauchau & Cardona
// 2007) so the matrix stays well conditioned as h -> 0. The geometric stiffness
// d(J^T lambda)/dq is left out of the matrix at first (it only changes the Newton
// rate); if the iteration contracts slowly (a correction more than 1/4 of the
// previous one, typical of large steps with large multipliers), it is added for the
// rest of the step by forward differences of J^T lambda (dense path only).
//
// The last iteration matrix of a step is kept for the next steps (modified Newton: the
// converged step solves the same residual equations, only the rate changes). A step with the
// kept matrix that contracts slowly (a correction more than 1/4 of the previous one), needs
// more than kKeptIterations, or has another step size is done again from its predictor as
// above, factoring at every iteration. A step converges when its last correction is below the
// Newton tolerance both in q_{n+1} (beta' |dvdot|, and |C|) and in v_{n+1} (gamma' |dvdot|):
// the kept matrix converges linearly, so its last correction is near the tolerance, and
// gamma' / beta' ~ 2 / h makes the velocity error the larger one. On spatial-chain-50 (n = 450, sparse) factoring at
// every iteration was 3/4 of the run time (stability matrix, issue 12). The sparse path
// orders the pattern (COLAMD) only when it changes.
#include "common.hpp"

#include <mbd/kit/formulation.hpp>
#include <mbd/kit/index3_problem.hpp>

#include <Eigen/Dense>
#include <Eigen/SparseLU>

#include <algorithm>
#include <cmath>

namespace mbd::integrators {
namespace {

constexpr int kMaxNewton = 25;
constexpr int kKeptIterations = 6;  // a step with the kept matrix that needs more factors again
constexpr int kDenseLimit = 400;  // iteration matrices up to this size are factored dense

class GeneralizedAlpha final : public Integrator {
public:
    explicit GeneralizedAlpha(const IntegratorSettings& settings) : settings_(settings) {}

    void begin(OdeProblem& problem, double t0, const Eigen::VectorXd& y0, double t_end,
               IntegratorStats& stats) override;
    bool step(double t_stop, StepOutputs* outputs) override;
    double time() const override { return t_; }
    const Eigen::VectorXd& state() const override { return y_; }

private:
    // Takes the formulation's index-3 problem, sizes the work vectors, and sets the
    // regularisation and the method's coefficients.
    void prepare(Index3Problem& dae);
    // One step from t to t + h: Newton on (vdot_{n+1}, lambda_{n+1}) with the kept iteration
    // matrix, else (none, or it converges slowly) with one factored at every iteration; then
    // the update.
    void step(double t, double h, IntegratorStats& stats);
    // The Newton iteration of step() into x_, lambda_. keep: with the kept matrix, false when
    // it contracts slowly or needs more than kKeptIterations; otherwise factoring at every
    // iteration, throwing DynamicsError when it does not converge.
    bool newton(double t, double h, IntegratorStats& stats, bool keep);
    // q, v and a at t_next from the current iterate x_ of vdot_{n+1}.
    void update_kinematics(double h, double t_next);
    // The problem's iteration matrix at the evaluated state (with the geometric stiffness at
    // lambda_ when asked, dense path only), regularised, and factored.
    void factor(double beta_p, double gamma_p, IntegratorStats& stats, bool geometric = false);
    // Solve the factored system for rhs_ into sol_.
    void solve();
    // Initial accelerations and multipliers: [M J^T; J 0] [vdot; lambda] = [Q; gamma].
    void initial_accelerations(double t, IntegratorStats& stats);
    // A Newton iteration that does not converge: a singular configuration when J lost rank
    // since the start (the problem's message, naming the rows), else the cause.
    [[noreturn]] void newton_failure(double t, const std::string& cause);

    IntegratorSettings settings_;
    OdeProblem* problem_ = nullptr;
    IntegratorStats* stats_ = nullptr;
    double t_ = 0.0;
    Eigen::VectorXd y_;  // the state at t_ as the problem's y
    FixedStepGrid grid_;
    Index3Problem* dae_ = nullptr;
    const Eigen::SparseMatrix<double>* mass_ = nullptr;
    int nv_ = 0, nc_ = 0;
    double regularization_ = 0.0;
    double alpha_m_ = 0.0, alpha_f_ = 0.0, gamma_ = 0.0, beta_ = 0.0;
    double newton_tol_ = 0.0;

    State state_;
    Eigen::VectorXd r_, rhs_, sol_;
    Eigen::VectorXd q_n_, v_n_, vdot_n_, a_n_, lambda_n_;
    Eigen::VectorXd x_, lambda_, a_next_, increment_;
    Eigen::MatrixXd dense_;
    Eigen::PartialPivLU<Eigen::MatrixXd> dense_lu_;
    Index3Problem::Triplets triplets_;
    Eigen::SparseMatrix<double> sparse_;
    Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> sparse_lu_;
    std::vector<int> analysed_outer_, analysed_inner_;  // the pattern sparse_lu_ was ordered for
    bool use_dense_ = true;
    // the kept iteration matrix (the last one factored in a step): whether there is one, and
    // the beta' it was built with
    bool factored_ = false;
    double factored_beta_p_ = 0.0;
};

void GeneralizedAlpha::factor(double beta_p, double gamma_p, IntegratorStats& stats, bool geometric) {
    triplets_.clear();
    dae_->iteration_matrix(beta_p, gamma_p, geometric && nc_ > 0 && use_dense_ ? &lambda_ : nullptr, triplets_);
    ++stats.jacobian_evaluations;
    if (use_dense_) {
        dense_.setZero();
        for (const Eigen::Triplet<double>& t : triplets_) dense_(t.row(), t.col()) += t.value();
        for (int i = 0; i < nc_; ++i) dense_(nv_ + i, nv_ + i) = -regularization_;
        dense_lu_.compute(dense_);
    } else {
        for (int i = 0; i < nc_; ++i) triplets_.emplace_back(nv_ + i, nv_ + i, -regularization_);
        sparse_.resize(nv_ + nc_, nv_ + nc_);
        sparse_.setFromTriplets(triplets_.begin(), triplets_.end());
        const int* outer = sparse_.outerIndexPtr();
        const int* inner = sparse_.innerIndexPtr();
        const size_t nnz = static_cast<size_t>(sparse_.nonZeros());
        if (analysed_inner_.size() != nnz || !std::equal(inner, inner + nnz, analysed_inner_.begin()) ||
            !std::equal(outer, outer + sparse_.outerSize() + 1, analysed_outer_.begin())) {
            sparse_lu_.analyzePattern(sparse_);  // a new pattern: order it (COLAMD)
            analysed_outer_.assign(outer, outer + sparse_.outerSize() + 1);
            analysed_inner_.assign(inner, inner + nnz);
        }
        sparse_lu_.factorize(sparse_);
        if (sparse_lu_.info() != Eigen::Success)
            throw DynamicsError(state_.t, "generalized_alpha: the iteration matrix is singular at t = " +
                                              format_time(state_.t) + " (redundant or singular constraints?)");
    }
}

void GeneralizedAlpha::solve() {
    if (use_dense_)
        sol_.noalias() = dense_lu_.solve(rhs_);
    else
        sol_ = sparse_lu_.solve(rhs_);
}

void GeneralizedAlpha::newton_failure(double t, const std::string& cause) {
    const ConstraintValues& cv = dae_->constraint_values();
    if (nc_ > 0 && cv.J.rows() == nc_) dae_->check_rank(t);  // throws on a lost rank
    std::string where;
    if (nc_ > 0 && cv.C.size() == nc_) {
        Eigen::Index worst = 0;
        const double c = cv.C.cwiseAbs().maxCoeff(&worst);
        where = "; worst constraint row: " + dae_->describe_row(static_cast<int>(worst)) +
                ", |C| = " + format_time(c);
    }
    throw DynamicsError(t, "generalized_alpha: Newton iteration did not converge at t = " + format_time(t) + " (" +
                               cause + where + "); try a smaller step");
}

void GeneralizedAlpha::initial_accelerations(double t, IntegratorStats& stats) {
    state_.t = t;
    dae_->evaluate(state_);
    ++stats.rhs_evaluations;
    dae_->set_reference_rank(t);
    factor(0.0, 0.0, stats);  // [M J^T; J 0]
    factored_ = false;        // not an iteration matrix
    rhs_.head(nv_) = dae_->forces();
    rhs_.tail(nc_) = dae_->constraint_values().gamma;
    solve();
    if (!sol_.allFinite())
        throw DynamicsError(t, "generalized_alpha: the initial accelerations cannot be solved at t = " +
                                   format_time(t) + " (singular mass matrix or constraints)");
    vdot_n_ = sol_.head(nv_);
    lambda_n_ = sol_.tail(nc_);
}

void GeneralizedAlpha::prepare(Index3Problem& dae) {
    dae_ = &dae;
    nv_ = dae.velocity_count();
    nc_ = dae.constraint_count();
    const int n = nv_ + nc_;
    use_dense_ = n <= kDenseLimit;
    factored_ = false;
    analysed_outer_.clear();
    analysed_inner_.clear();
    if (use_dense_) {
        dense_.resize(n, n);
        dense_lu_ = Eigen::PartialPivLU<Eigen::MatrixXd>(n);
    }
    r_.resize(nv_);
    rhs_.resize(n);
    sol_.resize(n);
    x_.resize(nv_);
    a_next_.resize(nv_);
    increment_.resize(nv_);

    // regularisation of the zero block: keeps consistent redundant constraints solvable
    mass_ = &dae.mass_matrix();
    const Eigen::SparseMatrix<double>& M = *mass_;
    double m_max = 0.0;
    for (int k = 0; k < M.outerSize(); ++k)
        for (Eigen::SparseMatrix<double>::InnerIterator it(M, k); it; ++it) m_max = std::max(m_max, std::abs(it.value()));
    regularization_ = m_max > 0.0 ? 1e-12 / m_max : 1e-12;

    const double rho = std::clamp(settings_.rho_infinity, 0.0, 1.0);
    alpha_m_ = (2.0 * rho - 1.0) / (rho + 1.0);
    alpha_f_ = rho / (rho + 1.0);
    gamma_ = 0.5 + alpha_f_ - alpha_m_;
    beta_ = 0.25 * (gamma_ + 0.5) * (gamma_ + 0.5);
    // Newton tolerance on position-level corrections (beta' |dvdot|) and on |C|.
    newton_tol_ = std::max(1e-3 * settings_.tolerance, 1e-14);
}

void GeneralizedAlpha::update_kinematics(double h, double t_next) {
    a_next_ = (alpha_f_ * vdot_n_ - alpha_m_ * a_n_ + (1.0 - alpha_f_) * x_) / (1.0 - alpha_m_);
    state_.v = v_n_ + (h * (1.0 - gamma_)) * a_n_ + (h * gamma_) * a_next_;
    increment_ = h * v_n_ + (h * h * (0.5 - beta_)) * a_n_ + (h * h * beta_) * a_next_;
    state_.q = q_n_;
    dae_->advance_positions(state_.q, increment_);
    state_.t = t_next;
}

void GeneralizedAlpha::step(double t, double h, IntegratorStats& stats) {
    const double beta_p = h * h * beta_ * (1.0 - alpha_f_) / (1.0 - alpha_m_);
    // a step within 0.1% of the kept matrix's (the rounding of t_next - t) keeps it
    const bool keep = factored_ && std::abs(factored_beta_p_ - beta_p) <= 1e-3 * beta_p;
    if (!keep || !newton(t, h, stats, true)) newton(t, h, stats, false);
    update_kinematics(h, t + h);
    a_n_ = a_next_;
    vdot_n_ = x_;
    lambda_n_ = lambda_;
    q_n_ = state_.q;
    v_n_ = state_.v;
    dae_->project_positions(q_n_);
    state_.q = q_n_;
}

bool GeneralizedAlpha::newton(double t, double h, IntegratorStats& stats, bool keep) {
    const double t_next = t + h;
    const double beta_p = h * h * beta_ * (1.0 - alpha_f_) / (1.0 - alpha_m_);
    const double gamma_p = h * gamma_ * (1.0 - alpha_f_) / (1.0 - alpha_m_);
    // predictor: accelerations and multipliers of the last step
    x_ = vdot_n_;
    lambda_ = lambda_n_;
    bool geometric = false;  // switched on when the iteration contracts slowly
    double first = 0.0, previous = 0.0;
    for (int it = 0; it < kMaxNewton; ++it) {
        update_kinematics(h, t_next);
        dae_->evaluate(state_);
        ++stats.rhs_evaluations;
        ++stats.newton_iterations;
        dae_->residual(x_, lambda_, r_);
        const Eigen::VectorXd& C = dae_->constraint_values().C;
        rhs_.head(nv_) = -r_;
        if (nc_ > 0) rhs_.tail(nc_) = -C / beta_p;
        if (!rhs_.allFinite()) {
            if (keep) return false;
            newton_failure(t_next, "the residual became non-finite");
        }
        if (!keep) {
            factor(beta_p, gamma_p, stats, geometric);
            factored_ = true;
            factored_beta_p_ = beta_p;
        }
        solve();
        if (!sol_.allFinite()) {
            if (keep) return false;
            newton_failure(t_next, "singular iteration matrix");
        }
        x_ += sol_.head(nv_);
        if (nc_ > 0) lambda_ += sol_.tail(nc_);
        const double correction = sol_.head(nv_).lpNorm<Eigen::Infinity>();
        const double dq = beta_p * correction;   // the correction's size in q_{n+1}
        const double dv = gamma_p * correction;  // and in v_{n+1} (gamma' / beta' ~ 2 / h times dq)
        const double c = nc_ > 0 ? C.lpNorm<Eigen::Infinity>() : 0.0;
        const double scale = std::max(1.0, q_n_.lpNorm<Eigen::Infinity>());
        const double v_scale = std::max(1.0, v_n_.lpNorm<Eigen::Infinity>());
        if (it == 0) first = dq;
        const bool slow = it >= 1 && dq > 0.25 * previous;
        const bool q_converged = dq <= newton_tol_ * scale && c <= newton_tol_ * scale;
        // A negligible correction in both q and v: accept. Checking q alone let the kept matrix's
        // linear rate stop with velocity errors 2 / h times larger (the whirling pendulum of
        // scenes/extreme drifted 0.019 in energy instead of 2.9e-6).
        if (q_converged && dv <= newton_tol_ * v_scale) return true;
        if (slow && keep) return false;  // the kept matrix is out of date: factor again
        // a fresh matrix whose correction stops shrinking with q converged: v's round-off floor
        if (q_converged && slow) return true;
        if (slow) geometric = true;
        previous = dq;
        if (keep && it + 1 >= kKeptIterations) return false;
        if (it > 2 && dq > 1e3 * std::max(first, newton_tol_)) newton_failure(t_next, "diverging corrections");
    }
    newton_failure(t_next, std::to_string(kMaxNewton) + " iterations");
}

void GeneralizedAlpha::begin(OdeProblem& problem, double t0, const Eigen::VectorXd& y0, double /*t_end*/,
                             IntegratorStats& stats) {
    Index3Problem* dae = problem.index3_problem();
    if (!dae)
        throw InputError(name(), "generalized_alpha needs the formulation's index-3 problem (Index3Problem: "
                                 "M vdot + J^T lambda = Q, C(q, t) = 0), which this problem's formulation does not "
                                 "provide; use one that does (augmented)");
    require_fixed_step(name(), settings_);
    prepare(*dae);
    problem_ = &problem;
    stats_ = &stats;
    dae->state_from_y(t0, y0, state_);
    state_.t = t0;
    q_n_ = state_.q;
    v_n_ = state_.v;
    t_ = t0;
    y_ = y0;
    grid_.start(t0);
    initial_accelerations(t0, stats);
    a_n_ = vdot_n_;
    x_ = vdot_n_;
    lambda_ = lambda_n_;
}

bool GeneralizedAlpha::step(double t_stop, StepOutputs* /*outputs: the steps end on each*/) {
    if (!problem_) throw InputError(name(), "step() before begin()");
    const double t_next = grid_.next(t_, t_stop, settings_.step);
    check_step_count(name(), settings_, *stats_, t_);
    step(t_, t_next - t_, *stats_);
    ++stats_->steps;
    grid_.taken();
    t_ = t_next;
    stop_if_interrupted(t_);  // a step boundary: SIGINT/SIGTERM/SIGHUP stop here
    state_.t = t_;
    state_.q = q_n_;
    state_.v = v_n_;
    dae_->y_from_state(state_, y_);
    return true;
}

}  // namespace

std::unique_ptr<Integrator> make_generalized_alpha(const IntegratorSettings& settings) {
    return std::make_unique<GeneralizedAlpha>(settings);
}

}  // namespace mbd::integrators
