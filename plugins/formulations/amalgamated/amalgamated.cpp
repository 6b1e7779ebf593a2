// The amalgamated formulation of the constrained equations of motion (Shabana,
// Computational Dynamics, Sec. 4.6, Eqs. 4.17-4.20): the Newton-Euler equations of all
// bodies with the generalized constraint forces Q_c as unknowns, the velocity
// transformation of the embedding technique and the orthogonality of Q_c to it,
//     M vdot = Q + Q_c                      (Eq. 4.17)
//     vdot = B vdot_i + gamma'              (Eq. 4.18; rows of the independent components
//                                            are the identification rows vdot_sel = vdot_i)
//     B^T Q_c = 0                           (Eq. 4.19)
// with B = [I; B_d] at the independent / dependent components, B_d = -J_d^-1 J_i (a coordinate
// partition of J, partition.hpp; book Eqs. 6.80-6.94). B is never formed: it is dense (n_v x k)
// in absolute coordinates, O(n^2) on a chain. Instead Eq. 4.20 is solved in the equivalent
// sparse form that B's definition gives:
//   - Eq. 4.18: on the independent components vdot_sel = vdot_i (the identification rows); on
//     the dependent ones vdot_d = B_d vdot_i + gamma'_d, i.e. (times J_d, gamma'_d = J_d^-1
//     gamma) J_d vdot_d + J_i vdot_sel = gamma: J vdot = gamma on the kept rows;
//   - Eq. 4.19: B^T Q_c = Q_c,i - J_i^T J_d^-T Q_c,d = 0, i.e. with mu = -J_d^-T Q_c,d,
//     Q_c = -J^T mu on the kept rows (range(J^T) is the orthogonal complement of range(B)).
// With f = -Q_c and mu (vdot_i is vdot at the independent components) these are
//     [ M   I    0   ] [ vdot ]   [ Q     ]
//     [ J   0    0   ] [ f    ] = [ gamma ]          (kept rows; a dropped row: mu_r = 0)
//     [ 0  -I   J^T  ] [ mu   ]   [ 0     ]
// whose third block row gives f = J^T mu; put into the first, the unknowns x = [vdot; mu] solve
//     [ M   J^T ] [ vdot ]   [ Q     ]
//     [ J   D   ] [ mu   ] = [ gamma ]               (D_rr = 1 for a dropped row, else 0)
// of size n_v + n_c, as sparse as J, factored by sparse LU with pivoting (KLU,
// fixed_pattern_lu.hpp), never reduced further by hand to the embedding equations (Eq. 6.95:
// dense B^T M B) or to the Schur complement J M^-1 J^T (the augmented formulation's route).
// The matrix is indefinite, so an LDL^T without pivoting (CHOLMOD) is not valid; KLU's LU
// with threshold pivoting is. The pattern is fixed for the life of the System (M's body
// blocks, J's pattern twice and a diagonal slot per constraint row, which decouples the rows
// the partition drops, explicit zeros kept): a re-selection changes values only. It is
// ordered once, factored with pivoting once, and at the following evaluations refactored in
// place with the same pivots (nothing is allocated), pivoting again only when the solution's
// backward error shows that those pivots no longer fit. mu are the multipliers of the kept
// rows (Q_c = -J^T lambda, book Eq. 6.128).
//
// State y = [q; v] as the augmented formulation; drift: the same projection after each
// accepted step (kit/include/mbd/kit/projection.hpp), or Baumgarte terms in gamma, or
// none (the projection's S = J M^-1 J^T dense or sparse by size: projection.hpp,
// sparse_metric.hpp). Reactions: lambda = mu (redundant rows get zero).
#include <mbd/kit/coordinate_selector.hpp>
#include <mbd/kit/rank_certificate.hpp>
#include <mbd/kit/partition_switch.hpp>
#include <mbd/kit/fixed_pattern_lu.hpp>
#include <mbd/kit/sparse_metric.hpp>
#include <mbd/kit/sparse_velocity_transform.hpp>

#include <mbd/kit/non_finite_motion.hpp>
#include <mbd/kit/coordinate_rates.hpp>
#include <mbd/kit/formulation.hpp>
#include <mbd/kit/ode_state.hpp>
#include <mbd/kit/partition.hpp>
#include <mbd/kit/projection.hpp>
#include <mbd/kit/singularity.hpp>
#include <mbd/sdk/text.hpp>
#include <mbd/kit/velocity_transform.hpp>

#include <Eigen/Dense>
#include <Eigen/Sparse>

#include <cmath>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

namespace mbd {
namespace {

class Amalgamated final : public CoordinateVelocityFormulation {
public:
    Amalgamated() = default;

    MBD_FORMULATION_CALLS;
    bool may_redefine_state() const override { return false; }  // y = [q; v] does not depend on the partition
    OptionGroups options_used() const override {
        return kStabilizationOptions | kPartitionOptions | kSingularityOptions;
    }

    // for tests
    const CoordinatePartition& partition() const { return part_; }
    int block_size() const { return nv_ + nc_; }

private:
    // state_ -> cv_, Q_, vdot_, mu_ (the block system, Eq. 4.20)
    void solve_dynamics(double t);
    void select(const State& state, bool initial);
    void build_pattern();
    // J's current entries (and the dropped rows' decoupling) into K_'s values
    void fill_J();
    // x_ = K^-1 rhs_ (KLU on the fixed pattern)
    void solve_block_system(double t);
    // the re-selection trigger at cv_.J: dense, J_d's pivot ratio for partition p (complete
    // pivoting); sparse, the current J_d's LU ratio relative to the partition's first
    // (sparse_velocity_transform.hpp)
    double pivot_ratio(const CoordinatePartition& p);
    void mark_dropped_rows();
    // r_ = rhs_ - K_ x_ and x_'s normwise backward error ||r|| / (||K|| ||x|| + ||rhs||) as a
    // solution of K_ x = rhs_ (infinity norms), in one pass over K_
    double residual();

    bool log_choices_ = false;  // FormulationOptions::log_choices, default false

    System* system_ = nullptr;
    FormulationOptions options_;
    int nc_ = 0;
    const Eigen::SparseMatrix<double>* M_ = nullptr;  // the System's M (block diagonal)
    bool sparse_ = false;  // selector_.sparse(): the projection's metric and the pivot ratio sparse
    CoordinatePartition part_;
    bool analysed_ = false;

    // scratch, sized in bind() or by the first evaluation: rhs() and project() allocate nothing
    State state_;
    ConstraintValues cv_;
    Eigen::MatrixXd J_;
    Eigen::VectorXd Q_, gamma_s_, Jv_, vdot_, mu_, rhs_, x_, r_, dx_;
    Eigen::VectorXd row_sums_;  // |K| 1, residual()'s
    std::vector<Eigen::Triplet<double>> triplets_;
    Eigen::SparseMatrix<double> K_;
    std::vector<int> j_slots_;         // per entry of J (storage order): its places in K_ (J and J^T)
    std::vector<int> decouple_slots_;  // per constraint row: the diagonal slot (row, mu_row) in K_
    std::vector<char> dropped_;        // per constraint row: dropped by the partition
    FixedPatternLU lu_;
    VelocityTransformWorkspace transform_;
    CoordinateSelector selector_;     // dense or sparse by size (coordinate_selector.hpp)
    CoordinatePartition fresh_;
    DenseMetricSolver metric_;
    SparseMetricSolver sparse_metric_;
    SparseVelocityTransform sparse_transform_;
    PartitionSwitch switch_;  // to a re-selected partition, keeping the one left
    ProjectionScratch projection_;
    SingularityMonitor singularity_;  // rank drop of J after an accepted step (singularity.hpp)
    RankCertificate rank_certificate_;  // lent to singularity_ (support/rank_certificate.hpp)
};

void Amalgamated::bind(System& system, const FormulationOptions& options) {
    system_ = &system;
    options_ = options;
    log_choices_ = options.log_choices.value_or(false) && options.log.enabled();  // no text built for nobody
    singularity_.tolerance = options.singularity_tolerance;
    bind_sizes(system);
    nc_ = system.constraint_rows(true);
    M_ = &system.mass_matrix();
    selector_.bind(nc_, nv_, options, fresh_);  // a re-selection allocates nothing (dense)
    sparse_ = selector_.sparse();
    if (sparse_)
        sparse_metric_.bind(system);
    else
        metric_.bind(system);
    singularity_.metric_distortion = sparse_ ? sparse_metric_.metric_distortion() : metric_.metric_distortion();
    singularity_.reset();
    rank_certificate_.bind(system, singularity_);
    state_.set_zero(nq_, nv_);
    Q_.setZero(nv_);
    vdot_.setZero(nv_);
    projection_.resize(nq_, nv_, nc_);
    mu_.setZero(nc_);
    for (Eigen::VectorXd* v : {&rhs_, &x_, &r_, &dx_, &row_sums_}) v->setZero(nv_ + nc_);
    dropped_.assign(nc_, 0);
    analysed_ = false;
    // the partition at the assembled initial state (the run assembles the same way)
    select(assembled_initial_state(system), true);
}

void Amalgamated::select(const State& state, bool initial) {
    system_->constraints(state, cv_, true);
    part_ = selector_.select(cv_.J, initial ? options_.partition.pivot_threshold : 1.0, options_.partition.rank_tolerance);
    if (sparse_) {
        sparse_transform_.select(cv_.J, part_);
        switch_.reset();
    }
    mark_dropped_rows();
    if (initial && !part_.redundant.empty())
        options_.log("amalgamated: " + redundant_rows_message(part_, [&](int r) { return system_->describe_row(r); }));
}

double Amalgamated::pivot_ratio(const CoordinatePartition& p) {
    if (!sparse_) {
        J_ = cv_.J;
        return dependent_pivot_ratio(J_, p, transform_);
    }
    return sparse_transform_.factor(cv_.J) ? sparse_transform_.relative_pivot_ratio() : 0.0;
}

void Amalgamated::mark_dropped_rows() {
    std::fill(dropped_.begin(), dropped_.end(), 0);
    for (int r : part_.redundant) dropped_[r] = 1;
}

// The block system of Eq. 4.20 with -Q_c eliminated (see the header), unknowns x = [vdot; mu].
void Amalgamated::build_pattern() {
    const int n = nv_, m = nc_;
    const Eigen::SparseMatrix<double>& J = cv_.J;
    triplets_.clear();
    triplets_.reserve(static_cast<size_t>(M_->nonZeros() + 2 * J.nonZeros() + m));
    // M: constant, so its stored entries are its pattern (planar diag(m, m, J); spatial diag(m I, Jbar)
    // with Jbar's nonzeros), not full body blocks whose structural zeros only add fill to the LU
    for (int c = 0; c < n; ++c)
        for (Eigen::SparseMatrix<double>::InnerIterator it(*M_, c); it; ++it)
            triplets_.emplace_back(static_cast<int>(it.row()), c, it.value());
    for (int c = 0; c < n; ++c)
        for (Eigen::SparseMatrix<double>::InnerIterator it(J, c); it; ++it) {
            triplets_.emplace_back(n + static_cast<int>(it.row()), c, 0.0);  // J vdot
            triplets_.emplace_back(c, n + static_cast<int>(it.row()), 0.0);  // J^T mu
        }
    for (int r = 0; r < m; ++r) triplets_.emplace_back(n + r, n + r, 0.0);  // mu_r = 0 when dropped
    K_.resize(n + m, n + m);
    K_.setFromTriplets(triplets_.begin(), triplets_.end());
    K_.makeCompressed();
    auto slot = [&](int row, int col) { return static_cast<int>(&K_.coeffRef(row, col) - K_.valuePtr()); };
    j_slots_.clear();
    for (int c = 0; c < n; ++c)
        for (Eigen::SparseMatrix<double>::InnerIterator it(J, c); it; ++it) {
            j_slots_.push_back(slot(n + static_cast<int>(it.row()), c));
            j_slots_.push_back(slot(c, n + static_cast<int>(it.row())));
        }
    decouple_slots_.resize(m);
    for (int r = 0; r < m; ++r) decouple_slots_[r] = slot(n + r, n + r);
}

void Amalgamated::fill_J() {
    const Eigen::SparseMatrix<double>& J = cv_.J;
    double* values = K_.valuePtr();
    size_t e = 0;
    for (int c = 0; c < J.outerSize(); ++c)
        for (Eigen::SparseMatrix<double>::InnerIterator it(J, c); it; ++it) {
            const double value = dropped_[it.row()] ? 0.0 : it.value();
            values[j_slots_[e++]] = value;
            values[j_slots_[e++]] = value;
        }
    for (int r = 0; r < nc_; ++r) values[decouple_slots_[r]] = dropped_[r] ? 1.0 : 0.0;
}

double Amalgamated::residual() {
    r_ = rhs_;  // rhs - K x
    row_sums_.setZero();
    for (int col = 0; col < K_.outerSize(); ++col)
        for (Eigen::SparseMatrix<double>::InnerIterator it(K_, col); it; ++it) {
            r_[it.row()] -= it.value() * x_[col];
            row_sums_[it.row()] += std::abs(it.value());
        }
    const double scale = row_sums_.maxCoeff() * x_.lpNorm<Eigen::Infinity>() + rhs_.lpNorm<Eigen::Infinity>();
    return scale > 0.0 ? r_.lpNorm<Eigen::Infinity>() / scale : 0.0;
}

void Amalgamated::solve_dynamics(double t) {
    System& sys = *system_;
    sys.constraints(state_, cv_, true);
    sys.generalized_forces(state_, Q_);
    if (!Q_.allFinite()) throw NonFiniteMotion(t, "non-finite generalized forces: the motion diverged (try a smaller tolerance or step)");
    gamma_s_ = cv_.gamma;
    if (options_.stabilization == Stabilization::Baumgarte && nc_ > 0) {
        const double a = options_.baumgarte_alpha, b = options_.baumgarte_beta;
        Jv_.noalias() = cv_.J * state_.v;
        Jv_ += cv_.C_t;
        gamma_s_ -= 2.0 * a * Jv_;
        gamma_s_ -= b * b * cv_.C;
    }
    const int n = nv_, m = nc_;
    rhs_.head(n) = Q_;
    rhs_.tail(m) = gamma_s_;
    for (int r : part_.redundant) rhs_[n + r] = 0.0;
    solve_block_system(t);
    if (!x_.allFinite()) throw DynamicsError(t, "amalgamated: non-finite solution of the block system (Eq. 4.20)");
    vdot_ = x_.head(n);
    mu_ = x_.tail(m);
}

// x_ = K^-1 rhs_ by KLU on K's fixed pattern, refactored in place with the last pivots while
// the solution's backward error says they still fit.
void Amalgamated::solve_block_system(double t) {
    bool pivot = false;
    double backward_error = 0.0;
    if (!analysed_) {  // the first evaluation: the pattern
        build_pattern();
        if (!lu_.analyze(K_)) throw DynamicsError(t, "amalgamated: the block system of Eq. 4.20 could not be ordered");
        analysed_ = true;
        pivot = true;
    }
    fill_J();
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
        backward_error = residual();
        // the pivots of the last pivoting factorization still fit (backward error near round-off)
        if (pivot || backward_error <= 1e-10) break;
        pivot = true;
    }
    // one step of iterative refinement when the solution is not backward stable to round-off
    // (old pivots that still fit, but lose digits; or pivot growth)
    if (backward_error > 16.0 * std::numeric_limits<double>::epsilon()) {
        dx_ = r_;
        lu_.solve(dx_);
        x_ += dx_;
    }
}

void Amalgamated::rhs(double t, const Eigen::VectorXd& y, Eigen::VectorXd& ydot) {
    if (!y.allFinite()) throw NonFiniteMotion(t, "non-finite state: the motion diverged (try a smaller tolerance or step)");
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
        // the augmented formulation's projection (projection.hpp), S = J M^-1 J^T dense or sparse
        projection_.q0 = state_.q;
        projection_.v0 = state_.v;
        const bool ok = sparse_ ? project_onto_constraints(
                                      sys, t, projection_, options_.projection_tolerance, state_, cv_,
                                      [&](bool robust) { sparse_metric_.factor(cv_.J, robust); },
                                      [&](Eigen::VectorXd& x) { sparse_metric_.solve(x); },
                                      [&](const Eigen::VectorXd& x, Eigen::VectorXd& out) { sparse_metric_.apply_Minv(x, out); })
                                : project_onto_constraints(
                                      sys, t, projection_, options_.projection_tolerance, state_, cv_,
                                      [&](bool robust) { metric_.factor(cv_.J, robust); },
                                      [&](Eigen::VectorXd& x) { metric_.solve(x); },
                                      [&](const Eigen::VectorXd& x, Eigen::VectorXd& out) { metric_.apply_Minv(x, out); });
        if (!ok) return false;
    }
    bool cv_at_state = projected;  // the projection leaves cv_ at the projected positions
    if (singularity_.active(sys)) {
        if (!cv_at_state) sys.constraints(state_, cv_, true);
        cv_at_state = true;
        // cv_ at the (projected) positions, where the velocity projection last factored S
        const double pivot = sparse_ ? sparse_metric_.least_relative_pivot() : metric_.least_relative_pivot();
        singularity_.check(sys, t, cv_.J, projected ? pivot : 0.0);
    }
    y.head(nq_) = state_.q;
    y.tail(nv_) = state_.v;
    // re-selection of the partition near a singular J_d (book Sec. 6.12); y = [q; v] does
    // not depend on the partition, so this can happen at any projection
    if (part_.rank > 0) {
        if (!cv_at_state) system_->constraints(state_, cv_, true);
        const double ratio = pivot_ratio(part_);
        if (ratio < options_.partition.reselect_ratio) {
            CoordinatePartition& fresh = fresh_;
            selector_.select(cv_.J, 1.0, options_.partition.rank_tolerance, {}, fresh);
            // sparse: the two compared like with like (coordinate_selector.hpp), not by the
            // trigger's relative ratio
            const double tolerance = options_.partition.rank_tolerance;
            const double current = sparse_ ? selector_.dependent_pivot_ratio(cv_.J, part_, tolerance) : ratio;
            const double candidate = sparse_ ? selector_.dependent_pivot_ratio(cv_.J, fresh, tolerance) : pivot_ratio(fresh);
            if (fresh.rank == part_.rank && !same_set(fresh.dependent, part_.dependent) && candidate > current) {
                // the same rank: K keeps its pattern and size
                if (sparse_)
                    switch_.to(cv_.J, fresh, part_, sparse_transform_);
                else
                    part_ = fresh;
                mark_dropped_rows();
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
    lambda = mu_;  // Q_c = -J^T mu on the kept rows (book Eq. 6.128); dropped rows 0
}

}  // namespace

std::unique_ptr<Formulation> make_amalgamated(const FormulationSpec&) { return std::make_unique<Amalgamated>(); }

}  // namespace mbd

MBD_FORMULATION_PLUGIN(amalgamated, mbd::make_amalgamated)
