// The amalgamated formulation of the constrained equations of motion (Shabana,
// Computational Dynamics, Sec. 4.6, Eqs. 4.17-4.20): the Newton-Euler equations of all
// bodies with the generalized constraint forces Q_c as unknowns, the velocity
// transformation of the embedding technique and the orthogonality of Q_c to it,
//     M vdot = Q + Q_c                      (Eq. 4.17)
//     vdot = B vdot_i + gamma'              (Eq. 4.18; rows of the independent components
//                                            are the identification rows vdot_sel = vdot_i)
//     B^T Q_c = 0                           (Eq. 4.19)
// assembled as ONE sparse symmetric (indefinite) system (Eq. 4.20)
//     [ M     I     0  ] [ vdot   ]   [ Q      ]
//     [ I     0    -B  ] [ -Q_c   ] = [ gamma' ]
//     [ 0   -B^T    0  ] [ vdot_i ]   [ 0      ]
// of size 2 n_v + k and solved by sparse LU with pivoting (KLU, fixed_pattern_lu.hpp), never
// reduced by hand to the embedding equations. B and gamma' come
// from a coordinate partition of J (partition.hpp, velocity_transform.hpp; book
// Eqs. 6.80-6.94). The matrix is symmetric but indefinite (its inertia has n_v + k
// negative eigenvalues), so an LDL^T without pivoting (CHOLMOD) is not valid; KLU's LU
// with threshold pivoting is. The pattern is fixed for the run (M's body blocks, the
// identities, and B as a dense n_v x k block, explicit zeros kept: a re-selection of the
// partition moves B's identity and zero rows but never leaves that block): it is ordered
// once, factored with pivoting once, and at the following evaluations, across
// re-selections, refactored in place with the same pivots (nothing is allocated),
// pivoting again only when the solution's backward error shows that those pivots no
// longer fit.
//
// State y = [q; v] as the augmented formulation; drift: the same projection after each
// accepted step (sdk/include/mbd/sdk/projection.hpp), or Baumgarte terms in gamma, or
// none. Reactions: lambda from Q_c = -J^T lambda (book Eq. 6.128) on the kept rows,
// J_d^T lambda = -Q_c,d (redundant rows get zero).
#include "fixed_pattern_lu.hpp"

#include <coordinate_selector.hpp>

#include <mbd/sdk/coordinate_rates.hpp>
#include <mbd/sdk/formulation.hpp>
#include <mbd/sdk/ode_state.hpp>
#include <mbd/sdk/partition.hpp>
#include <mbd/sdk/projection.hpp>
#include <mbd/sdk/singularity.hpp>
#include <mbd/sdk/text.hpp>
#include <mbd/sdk/velocity_transform.hpp>

#include <Eigen/Dense>
#include <Eigen/Sparse>

#include <cmath>
#include <iostream>
#include <string>
#include <vector>

namespace mbd {
namespace {

class Amalgamated final : public CoordinateVelocityFormulation {
public:
    Amalgamated() = default;

    void bind(System& system, const FormulationOptions& options) override;
    void rhs(double t, const Eigen::VectorXd& y, Eigen::VectorXd& ydot) override;
    bool project(double t, Eigen::VectorXd& y) override;
    void multipliers(const State& state, Eigen::VectorXd& lambda) override;
    void accelerations(const State& state, Eigen::VectorXd& vdot) override;
    bool may_redefine_state() const override { return false; }  // y = [q; v] does not depend on the partition
    OptionGroups options_used() const override {
        return kStabilizationOptions | kPartitionOptions | kSingularityOptions;
    }

    // for tests
    const CoordinatePartition& partition() const { return part_; }
    int block_size() const { return 2 * nv_ + static_cast<int>(part_.independent.size()); }

private:
    // state_ -> cv_, J_, Q_, vdot_, Qc_ (the block system, Eq. 4.20)
    void solve_dynamics(double t);
    void select(const State& state, bool initial);
    void build_pattern();
    // B's current entries into K_'s values (the pattern of build_pattern(), all of B)
    void fill_B();
    // the normwise backward error of x as a solution of K_ x = rhs_, with r_ = rhs_ - K_ x
    double backward_error();

    bool log_choices_ = false;  // FormulationOptions::log_choices, default false

    System* system_ = nullptr;
    FormulationOptions options_;
    int nc_ = 0, nvb_ = 3;
    Eigen::MatrixXd Mdense_;
    CoordinatePartition part_;
    bool analysed_ = false;

    // scratch, sized in bind() or by the first evaluation: rhs() and project() allocate nothing
    State state_;
    ConstraintValues cv_;
    Eigen::MatrixXd J_, B_;
    Eigen::VectorXd Q_, gamma_s_, Jv_, gamma_prime_, vdot_, Qc_, rhs_, x_, r_, dx_;
    Eigen::VectorXd row_sums_;
    std::vector<Eigen::Triplet<double>> triplets_;
    Eigen::SparseMatrix<double> K_;
    std::vector<int> b_slots_;  // per column c and row of B: the value indices of -B and -B^T in K_
    FixedPatternLU lu_;
    VelocityTransformWorkspace transform_;
    CoordinateSelector selector_;     // dense or sparse by size (coordinate_selector.hpp)
    CoordinatePartition fresh_;
    DenseMetricSolver metric_;
    ProjectionScratch projection_;
    SingularityMonitor singularity_;  // rank drop of J after an accepted step (singularity.hpp)
};

void Amalgamated::bind(System& system, const FormulationOptions& options) {
    system_ = &system;
    options_ = options;
    log_choices_ = options.log_choices.value_or(false) && options.log.enabled();  // no text built for nobody
    singularity_.tolerance = options.singularity_tolerance;
    bind_sizes(system);
    nc_ = system.constraint_rows(true);
    nvb_ = velocities_per_body(system.dimension());
    Mdense_ = Eigen::MatrixXd(system.mass_matrix());
    metric_.bind(system);
    singularity_.metric_distortion = metric_.metric_distortion();
    singularity_.reset();
    state_.q.setZero(nq_);
    state_.v.setZero(nv_);
    Q_.setZero(nv_);
    vdot_.setZero(nv_);
    Qc_.setZero(nv_);
    projection_.resize(nq_, nv_, nc_);
    selector_.bind(nc_, nv_, options, fresh_);  // a re-selection allocates nothing (dense)
    analysed_ = false;
    // the partition at the assembled initial state (the run assembles the same way)
    select(assembled_initial_state(system), true);
}

void Amalgamated::select(const State& state, bool initial) {
    system_->constraints(state, cv_, true);
    J_ = cv_.J;
    part_ = selector_.select(cv_.J, initial ? options_.partition.pivot_threshold : 1.0, options_.partition.rank_tolerance);
    analysed_ = false;
    if (initial && !part_.redundant.empty())
        options_.log("amalgamated: " + redundant_rows_message(part_, [&](int r) { return system_->describe_row(r); }));
}

// The block matrix of Eq. 4.20 with unknowns x = [vdot; -Q_c; vdot_i].
void Amalgamated::build_pattern() {
    const int n = nv_, k = static_cast<int>(part_.independent.size());
    triplets_.clear();
    triplets_.reserve(static_cast<size_t>(n * nvb_ + 2 * n + 2 * n * k));
    // M (per-body blocks, explicit zeros kept so that the pattern never changes)
    for (int b = 0; b < n / nvb_; ++b)
        for (int i = 0; i < nvb_; ++i)
            for (int j = 0; j < nvb_; ++j) triplets_.emplace_back(b * nvb_ + i, b * nvb_ + j, Mdense_(b * nvb_ + i, b * nvb_ + j));
    // the identities coupling vdot and -Q_c
    for (int i = 0; i < n; ++i) {
        triplets_.emplace_back(i, n + i, 1.0);
        triplets_.emplace_back(n + i, i, 1.0);
    }
    // -B and -B^T, every row: B's rows of the independent components are the identification
    // rows (vdot_row - vdot_i,c = 0: a 1 in column c, zeros elsewhere), the others dependent
    for (int c = 0; c < k; ++c)
        for (int row = 0; row < n; ++row) {
            triplets_.emplace_back(n + row, 2 * n + c, -B_(row, c));
            triplets_.emplace_back(2 * n + c, n + row, -B_(row, c));
        }
    K_.resize(2 * n + k, 2 * n + k);
    K_.setFromTriplets(triplets_.begin(), triplets_.end());
    b_slots_.clear();
    for (int c = 0; c < k; ++c)
        for (int row = 0; row < n; ++row) {
            b_slots_.push_back(static_cast<int>(&K_.coeffRef(n + row, 2 * n + c) - K_.valuePtr()));
            b_slots_.push_back(static_cast<int>(&K_.coeffRef(2 * n + c, n + row) - K_.valuePtr()));
        }
}

void Amalgamated::fill_B() {
    const int k = static_cast<int>(part_.independent.size());
    double* values = K_.valuePtr();
    size_t slot = 0;
    for (int c = 0; c < k; ++c)
        for (int row = 0; row < nv_; ++row) {
            values[b_slots_[slot++]] = -B_(row, c);
            values[b_slots_[slot++]] = -B_(row, c);
        }
}

double Amalgamated::backward_error() {
    row_sums_.setZero(K_.rows());
    for (int col = 0; col < K_.outerSize(); ++col)
        for (Eigen::SparseMatrix<double>::InnerIterator it(K_, col); it; ++it) row_sums_[it.row()] += std::abs(it.value());
    const double scale = row_sums_.maxCoeff() * x_.lpNorm<Eigen::Infinity>() + rhs_.lpNorm<Eigen::Infinity>();
    return scale > 0.0 ? r_.lpNorm<Eigen::Infinity>() / scale : 0.0;
}

void Amalgamated::solve_dynamics(double t) {
    System& sys = *system_;
    sys.constraints(state_, cv_, true);
    J_ = cv_.J;
    sys.generalized_forces(state_, Q_);
    if (!Q_.allFinite()) throw DynamicsError(t, "non-finite generalized forces: the motion diverged (try a smaller tolerance or step)");
    gamma_s_ = cv_.gamma;
    if (options_.stabilization == Stabilization::Baumgarte && nc_ > 0) {
        const double a = options_.baumgarte_alpha, b = options_.baumgarte_beta;
        Jv_.noalias() = cv_.J * state_.v;
        Jv_ += cv_.C_t;
        gamma_s_ -= 2.0 * a * Jv_;
        gamma_s_ -= b * b * cv_.C;
    }
    // B and gamma' (Eqs. 4.18, 6.80-6.94) from the partition
    if (!velocity_transform(J_, gamma_s_, part_, B_, gamma_prime_, transform_))
        throw DynamicsError(t, "amalgamated: the dependent sub-Jacobian J_d is singular");
    const int n = nv_, k = static_cast<int>(part_.independent.size());
    bool pivot = false;
    if (!analysed_) {  // the first evaluation: the pattern
        build_pattern();
        if (!lu_.analyze(K_)) throw DynamicsError(t, "amalgamated: the block system of Eq. 4.20 could not be ordered");
        analysed_ = true;
        pivot = true;
    } else {
        fill_B();
    }
    rhs_.setZero(2 * n + k);
    rhs_.head(n) = Q_;
    rhs_.segment(n, n) = gamma_prime_;
    for (;;) {
        if (!lu_.factor(K_, pivot)) {
            if (!pivot) {
                pivot = true;
                continue;
            }
            throw DynamicsError(t, "amalgamated: the block system of Eq. 4.20 is singular");
        }
        x_ = rhs_;
        lu_.solve(x_);
        r_.noalias() = K_ * x_;
        r_ = rhs_ - r_;
        // the pivots of the last pivoting factorization still fit (backward error near round-off)
        if (pivot || backward_error() <= 1e-10) break;
        pivot = true;
    }
    // one step of iterative refinement (the identity blocks and M can differ by orders of magnitude)
    dx_ = r_;
    lu_.solve(dx_);
    x_ += dx_;
    if (!x_.allFinite()) throw DynamicsError(t, "amalgamated: non-finite solution of the block system (Eq. 4.20)");
    vdot_ = x_.head(n);
    Qc_ = -x_.segment(n, n);
}

void Amalgamated::rhs(double t, const Eigen::VectorXd& y, Eigen::VectorXd& ydot) {
    if (!y.allFinite()) throw DynamicsError(t, "non-finite state: the motion diverged (try a smaller tolerance or step)");
    from_ode(t, y, state_);
    solve_dynamics(t);
    ydot.resize(nq_ + nv_);
    write_coordinate_rates(system_->dimension(), state_.q, state_.v, ydot.head(nq_));
    ydot.tail(nv_) = vdot_;
}

bool Amalgamated::project(double t, Eigen::VectorXd& y) {
    System& sys = *system_;
    from_ode(t, y, state_);
    sys.normalize(state_.q);
    const bool projected = options_.stabilization == Stabilization::Projection && nc_ > 0;
    if (projected) {
        // the augmented formulation's projection (projection.hpp), dense S = J M^-1 J^T
        projection_.q0 = state_.q;
        projection_.v0 = state_.v;
        const bool ok = project_onto_constraints(
            sys, t, projection_, options_.projection_tolerance, state_, cv_,
            [&](bool robust) { metric_.factor(cv_.J, robust); }, [&](Eigen::VectorXd& x) { metric_.solve(x); },
            [&](const Eigen::VectorXd& x, Eigen::VectorXd& out) { metric_.apply_Minv(x, out); });
        if (!ok) return false;
    }
    if (singularity_.active(sys)) {
        if (!projected) sys.constraints(state_, cv_, true);
        // cv_ at the (projected) positions, where the velocity projection last factored S
        singularity_.check(sys, t, cv_.J, projected ? metric_.least_relative_pivot() : 0.0);
    }
    y.head(nq_) = state_.q;
    y.tail(nv_) = state_.v;
    // re-selection of the partition near a singular J_d (book Sec. 6.12); y = [q; v] does
    // not depend on the partition, so this can happen at any projection
    if (part_.rank > 0) {
        system_->constraints(state_, cv_, true);
        J_ = cv_.J;
        const double ratio = dependent_pivot_ratio(J_, part_, transform_);
        if (ratio < options_.partition.reselect_ratio) {
            CoordinatePartition& fresh = fresh_;
            selector_.select(cv_.J, 1.0, options_.partition.rank_tolerance, {}, fresh);
            if (fresh.rank == part_.rank && dependent_pivot_ratio(J_, fresh, transform_) > ratio) {
                part_ = fresh;  // the same rank: K keeps its pattern and size
                if (log_choices_) options_.log("amalgamated: t = " + format_time(t) + ": new coordinate partition");
            }
        }
    }
    return true;
}

void Amalgamated::accelerations(const State& state, Eigen::VectorXd& vdot) {
    state_ = state;
    solve_dynamics(state.t);
    vdot = vdot_;
}

void Amalgamated::multipliers(const State& state, Eigen::VectorXd& lambda) {
    state_ = state;
    solve_dynamics(state.t);
    // Q_c = -J^T lambda (book Eq. 6.128): J_d^T lambda_kept = -Q_c,d
    multipliers_from_dependent_rows(J_, part_, Eigen::VectorXd(-Qc_), lambda, transform_);
}

}  // namespace

std::unique_ptr<Formulation> make_amalgamated(const FormulationSpec&) { return std::make_unique<Amalgamated>(); }

}  // namespace mbd

MBD_FORMULATION_PLUGIN(amalgamated, mbd::make_amalgamated)
