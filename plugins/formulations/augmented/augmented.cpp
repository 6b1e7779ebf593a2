// The augmented formulation of the constrained equations of motion (Shabana,
// Computational Dynamics, Secs. 6.6-6.7; spatial form Sec. 7.9):
//
//     [ M  J^T ] [ vdot   ]   [ Q     ]
//     [ J  0   ] [ lambda ] = [ gamma ]          (book Eq. 6.141; Eq. 7.157 spatial)
//
// M is the constant block-diagonal mass matrix (planar diag(m, m, J), spatial
// diag(m I, Jbar)), J = C_q the constraint Jacobian with respect to v, Q the applied
// generalized forces (plus the gyroscopic term, book Eq. 7.155), gamma = Q_d (book
// Eq. 6.140), so that Cddot = J vdot - gamma = 0 (Eq. 6.139).
//
// State y = [q; v]; y' = [qdot(q, v); vdot] with qdot = v planar and, spatial,
// Rdot = v_R, pdot = 1/2 Gbar^T wbar (book Eq. 8.48 in Euler parameters).
//
// Linear algebra: the KKT matrix is symmetric INDEFINITE (digest erratum: the book's
// L8576 calls it positive definite), so it is not factored directly. M is block
// diagonal SPD, so the range-space (Schur complement) route is used (the block
// inverse of Eqs. 6.142-6.145):
//     S = J M^-1 J^T,   S lambda = J M^-1 Q - gamma,   vdot = M^-1 (Q - J^T lambda).
// With M^-1 = Lm Lm^T (per-body Cholesky factors) S = W W^T, W = J Lm.
//   dense : S summed body block by body block and factored by Cholesky with symmetric
//           pivoting (kit dense_gram.hpp);
//           a (near) rank-deficient S (redundant constraints) falls back to the
//           minimum-norm solution by a complete orthogonal decomposition, accepted
//           only if the acceleration constraints are then satisfied.
//   sparse: W W^T formed on its fixed pattern and factored L D L^T (sparse_gram.hpp);
//           the ordering and symbolic analysis are done once in bind() on W's fixed
//           pattern (every row of a joint touches every velocity column of that joint's
//           bodies); structurally redundant rows are left out as on the dense path
//           (below); a rank-deficient S is damped (W W^T + delta I) and refined.
// Velocity-level (nonholonomic) joint rows A v = b (a wheel's no-slip condition) are rows
// of J with their own multipliers (the no-slip reactions), written as C = 0, J = A, C_t = -b,
// gamma = db/dt - (dA/dt) v (System::constraints_with_velocity_rows): they enter the
// acceleration system and the velocity projection like any row, and restrict no position.
// Drift (FormulationOptions::stabilization): projection after each accepted step
// (Newton on C(q, t) = 0 with steps of minimum kinetic-energy norm,
// dq = -M^-1 J^T S^-1 C, then v <- v - M^-1 J^T S^-1 (J v + C_t)); Baumgarte
// (book Sec. 6.12, L9420-9442: gamma - 2 alpha (J v + C_t) - beta^2 C); or none.
#include <mbd/kit/non_finite_motion.hpp>
#include <mbd/kit/block_mass_inverse.hpp>
#include <mbd/kit/dense_gram.hpp>
#include <mbd/kit/formulation.hpp>
#include <mbd/kit/index3_problem.hpp>
#include <mbd/kit/ode_state.hpp>
#include <mbd/kit/projection.hpp>
#include <mbd/kit/reaction_loads.hpp>
#include <mbd/kit/singularity.hpp>
#include <mbd/sdk/text.hpp>

#include <mbd/kit/sparse_gram.hpp>
#include <mbd/kit/rank_certificate.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace mbd {
namespace {

class Augmented final : public CoordinateVelocityFormulation {
public:
    Augmented() = default;
    Augmented(const Augmented&) = delete;
    Augmented& operator=(const Augmented&) = delete;

    MBD_FORMULATION_CALLS;
    // its equations as the index-3 DAE (kit index3_problem.hpp), for generalized_alpha
    Index3Problem* index3_problem() override { return &index3_; }
    bool supports_velocity_constraints() const override { return true; }
    bool supports_reaction_loads() const override { return true; }
    // flexible bodies: a constant mass block is factored once, one that varies at each state
    // (kit block_mass_inverse.hpp), and S = J M^-1 J^T is formed densely (kit dense_gram.hpp)
    bool supports_flexible_bodies() const override { return true; }
    bool may_redefine_state() const override { return false; }  // y = [q; v] whatever rows are kept
    OptionGroups options_used() const override {
        return kStabilizationOptions | kLinearAlgebraOptions | kSingularityOptions;
    }

private:
    // state_ -> cv_, Q_, vdot_, lambda_ (and the reaction loads, solved with lambda_)
    void solve_dynamics(double t);
    // lambda_, vdot_ from cv_, Q_ and the right-hand side b_ = gamma_s (Eqs. 6.142-6.145)
    void solve_multipliers(double t, double gamma_norm);
    // the loads from joint reactions and the multipliers together (reaction_loads.hpp)
    void solve_reaction_loads(double t);
    // solve_dynamics() at a given state (copied into state_ without reallocating)
    void solve_at(const State& state);
    // factor S = J M^-1 J^T from cv_.J (dense or sparse); throws DynamicsError if singular
    void factor(double t, const char* what, bool robust = false);
    // x <- S^-1 x (after factor())
    void solve_S(Eigen::VectorXd& x);
    // out = M^-1 x
    void apply_Minv(const Eigen::VectorXd& x, Eigen::VectorXd& out) const { mass_inverse_.apply(x, out); }
    void redundant_rows_error(double t, const char* what) const;
    // the last factorization's least relative pivot (singularity.hpp's screen), 0 if robust
    double last_relative_pivot() const {
        if (rank_deficient_ || !dropped_.empty()) return 0.0;
        return sparse_ ? sparse_gram_.least_relative_pivot() : dense_.least_relative_pivot();
    }
    // rows dependent at the first evaluated (assembled) state: see dropped_
    void find_structural_redundancy(double t);
    bool reselect_dropped_rows(double t);
    void keep_all_rows();
    bool left_out_rows_hold() const;
    void check_finite(double t, const Eigen::VectorXd& x, const char* what) const;

    System* system_ = nullptr;
    SystemIndex3Problem index3_{*this};  // bound with the formulation
    FormulationOptions options_;
    bool sparse_ = false;
    bool planar_ = true;
    int nb_ = 0, nc_ = 0, nvb_ = 3, nqb_ = 3;

    // per body: M^-1 block and its lower Cholesky factor Lm (M^-1 = Lm Lm^T)
    BlockMassInverse mass_inverse_;
    // flexible bodies whose mass varies (null: none): their blocks re-evaluated and re-factored
    // at each state (refresh_mass), the constant ones kept as bound
    VaryingMass* varying_mass_ = nullptr;
    void refresh_mass(double t, const Eigen::VectorXd& q) {
        if (!varying_mass_) return;
        varying_mass_->update_mass_matrix(q);
        mass_inverse_.refresh(*system_, varying_mass_->varying_mass_blocks(), t);
    }

    // scratch (allocated in bind)
    State state_;
    ConstraintValues cv_;
    Eigen::VectorXd Q_, vdot_, lambda_, b_, tmp_nv_, tmp_nv2_, tmp_nc_, r_nc_, dv_;
    ProjectionScratch projection_;
    DenseGram dense_;  // dense path: S formed by body blocks
    // near rank-deficient S: the pseudo-inverse (dense) or damped least squares (sparse)
    bool rank_deficient_ = false;
    // sparse path: S = W W^T on W's fixed pattern
    SparseGram sparse_gram_;
    // rank drop of J after an accepted step: a singular configuration (kit singularity.hpp)
    SingularityMonitor singularity_;
    RankCertificate rank_certificate_;  // lent to singularity_ (support/rank_certificate.hpp)
    ReactionLoadSolver reaction_loads_;
    // Structurally redundant rows (dependent at the assembled initial state, e.g. the Bricard's
    // sixth joint) are left out of S with zero multipliers (dense and sparse paths), as the embedding
    // formulation drops them: off the manifold such a row is only NEARLY dependent, and its tiny
    // singular value in J would otherwise produce huge multipliers and accelerations. Which row
    // is the dependent one can change along the motion: when the kept rows become ill-conditioned
    // they are re-selected (as the embedding re-selects its coordinates). If a left-out row stops
    // being dependent (its acceleration constraint fails), every row is used again.
    // The sparse path selects them in the same way, from W formed densely, up to
    // kDenseSelectionEntries entries of W (32 MB); beyond, it keeps every row and solves a
    // rank-deficient S by damped least squares.
    static constexpr double kDenseSelectionEntries = 4e6;
    std::vector<int> dropped_;
    std::vector<char> is_dropped_;
    bool redundancy_checked_ = false;
    Eigen::MatrixXd selection_W_;  // sparse path: W = J Lm with every row, for a selection
};

void Augmented::bind(System& system, const FormulationOptions& options) {
    system_ = &system;
    index3_.bind(system);
    options_ = options;
    singularity_.tolerance = options.singularity_tolerance;

    planar_ = system.dimension() == Dimension::Planar;
    nvb_ = velocities_per_body(system.dimension());
    nqb_ = coordinates_per_body(system.dimension());
    nb_ = system.body_count();
    bind_sizes(system);
    nc_ = system.constraint_rows(true) + system.velocity_constraint_rows();
    sparse_ = options_.algebra == LinearAlgebra::Sparse ||
              (options_.algebra == LinearAlgebra::Auto && nv_ > options_.sparse_threshold);
    if (system.flexible_coordinates() > 0) sparse_ = false;  // the sparse S is formed by rigid body blocks only

    // M^-1 per body and its Cholesky factor (M is constant: book Eqs. 6.61-6.63)
    varying_mass_ = varying_mass(system);
    if (varying_mass_) varying_mass_->update_mass_matrix(system.initial_state().q);
    mass_inverse_.bind(system, "augmented formulation");
    reaction_loads_.bind(system);
    singularity_.metric_distortion = mass_inverse_.distortion();
    rank_certificate_.bind(system, singularity_);

    state_.set_zero(nq_, nv_);
    Q_.setZero(nv_);
    vdot_.setZero(nv_);
    lambda_.setZero(nc_);
    b_.setZero(nc_);
    tmp_nc_.setZero(nc_);
    r_nc_.setZero(nc_);
    projection_.resize(nq_, nv_, nc_);
    tmp_nv_.setZero(nv_);
    tmp_nv2_.setZero(nv_);
    dv_.setZero(nv_);
    cv_.C.setZero(nc_);
    cv_.C_t.setZero(nc_);
    cv_.gamma.setZero(nc_);
    rank_deficient_ = false;
    singularity_.reset();
    keep_all_rows();
    redundancy_checked_ = false;

    if (!sparse_) {
        dense_.resize(nc_, nv_);
        return;
    }

    // Sparse: the fixed pattern of W = J Lm, column by column. Column c of body b holds
    // every row of every joint or driver that connects body b.
    std::vector<std::vector<int>> rows_of_body(nb_);
    auto add_rows = [&](const std::vector<int>& bodies, int first, int count) {
        for (int body : bodies)
            if (body >= 0)
                for (int r = first; r < first + count; ++r) rows_of_body[body].push_back(r);
    };
    for (int j = 0; j < system.joint_count(); ++j) {
        const JointInfo& info = system.joint(j);
        add_rows(info.bodies, info.first_row, info.rows);
        add_rows(info.bodies, system.constraint_rows(true) + info.velocity_row_offset, info.velocity_rows);
    }
    for (int d = 0; d < system.driver_count(); ++d) {
        const DriverInfo& info = system.driver(d);
        add_rows(system.joint(info.joint).bodies, info.row, 1);
    }
    std::vector<std::vector<int>> rows_of_column(nv_);
    for (int b = 0; b < nb_; ++b) {
        auto& rows = rows_of_body[b];
        std::sort(rows.begin(), rows.end());
        rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
        for (int c = 0; c < nvb_; ++c) rows_of_column[b * nvb_ + c] = rows;
    }
    sparse_gram_.analyze(nc_, nv_, rows_of_column);
}

void Augmented::check_finite(double t, const Eigen::VectorXd& x, const char* what) const {
    if (x.allFinite()) return;
    int worst = 0;
    while (worst < x.size() && std::isfinite(x[worst])) ++worst;
    std::string where;
    if (worst < x.size() && x.size() == nv_ && worst < nb_ * nvb_)
        where = " (body '" + system_->body(worst / nvb_).name + "')";
    throw NonFiniteMotion(t, std::string("non-finite ") + what + where +
                               ": the motion diverged (try a smaller tolerance or step)");
}

void Augmented::redundant_rows_error(double t, const char* what) const {
    // Name the rows that depend on the others: a column-pivoted QR of J^T puts the
    // independent rows first; the rest are redundant in this configuration.
    std::string rows;
    if (static_cast<double>(nc_) * nv_ <= 4e6) {
        Eigen::MatrixXd Jt = Eigen::MatrixXd(cv_.J).transpose();
        Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(Jt);
        qr.setThreshold(1e-6);
        // at least the weakest row, when the rows are only nearly dependent
        const int rank = std::min(static_cast<int>(qr.rank()), nc_ - 1);
        const auto& perm = qr.colsPermutation().indices();
        int listed = 0;
        for (int k = rank; k < nc_ && listed < 8; ++k, ++listed)
            rows += (rows.empty() ? "" : ", ") + system_->describe_row(perm[k]);
        if (nc_ - rank > 8) rows += ", ...";
        if (!rows.empty())
            rows = "; " + std::to_string(nc_ - rank) + " of " + std::to_string(nc_) +
                   " constraint rows are (nearly) dependent on the others: " + rows;
    } else if (sparse_ && sparse_gram_.failed_row() >= 0) {
        rows = "; the rows are dependent at " + system_->describe_row(sparse_gram_.failed_row());
    }
    throw DynamicsError(t, std::string("singular saddle point (") + what +
                               "): the constraint Jacobian has dependent rows" + rows +
                               " (remove redundant joints, or check for a locked or singular position)");
}

void Augmented::factor(double t, const char* what, bool robust) {
    const Eigen::SparseMatrix<double>& J = cv_.J;
    rank_deficient_ = false;
    if (nc_ == 0) return;
    if (!sparse_) {
        // a decoupled (left-out) row: its multiplier is its (zero) right-hand side
        const double pivot_ratio = dense_.factor(J, mass_inverse_, dropped_);
        if (!dropped_.empty() && !robust && pivot_ratio <= 1e-6 && reselect_dropped_rows(t)) {
            factor(t, what, robust);  // with the new selection (it differs, so this recursion ends)
            return;
        }
        if (robust || pivot_ratio <= 1e-8) {
            // (near) rank deficient (redundant constraints, or close to it): the minimum-norm
            // multipliers (dense_gram.hpp); the caller checks J vdot = gamma
            dense_.factor_pseudo_inverse(J, mass_inverse_, dropped_);
            rank_deficient_ = true;
        }
        return;
    }
    // sparse: W = J Lm on W's fixed pattern, the dropped rows decoupled (their multipliers are 0)
    sparse_gram_.fill(J, mass_inverse_, &is_dropped_);
    bool factored = sparse_gram_.factor(0.0);
    if (!dropped_.empty() && !robust && (!factored || sparse_gram_.least_relative_pivot() <= 1e-6)) {
        if (reselect_dropped_rows(t)) {
            factor(t, what, robust);  // with the new selection (it differs, so this recursion ends)
            return;
        }
        sparse_gram_.fill(J, mass_inverse_, &is_dropped_);  // the selection read W with every row
        factored = sparse_gram_.factor(0.0);
    }
    if (!robust && factored) return;
    // rank deficient: damped least squares (W W^T + delta I), refined and checked by the caller
    if (!sparse_gram_.factor(1e-12 * std::max(sparse_gram_.max_diagonal(), 1e-300))) redundant_rows_error(t, what);
    rank_deficient_ = true;
}

void Augmented::solve_S(Eigen::VectorXd& x) {
    if (nc_ == 0) return;
    for (int r : dropped_) x[r] = 0.0;
    if (!sparse_) {
        dense_.solve(x);
        return;
    }
    sparse_gram_.solve(x, rank_deficient_ ? 2 : 0);  // two refinements against the undamped S when damped
    for (int r : dropped_) x[r] = 0.0;
}

// At a projected state (cv_ there, state_.v projected on the kept rows): do the left-out rows
// hold too, in position and velocity, as rows that depend on the kept ones must?
bool Augmented::left_out_rows_hold() const {
    const double position_tolerance = 1e3 * std::max(options_.projection_tolerance, 1e-12);
    for (int r : dropped_) {
        if (std::abs(cv_.C[r]) > position_tolerance) return false;
        double jv = cv_.C_t[r], scale = 1.0 + std::abs(cv_.C_t[r]);
        for (int c = 0; c < cv_.J.outerSize(); ++c)
            for (Eigen::SparseMatrix<double>::InnerIterator it(cv_.J, c); it; ++it)
                if (it.row() == r) jv += it.value() * state_.v[c], scale += std::abs(it.value() * state_.v[c]);
        if (std::abs(jv) > 1e-6 * scale) return false;
    }
    return true;
}

void Augmented::keep_all_rows() {
    dropped_.clear();
    is_dropped_.assign(nc_, 0);
}

void Augmented::find_structural_redundancy(double t) {
    redundancy_checked_ = true;
    // beyond kDenseSelectionEntries the sparse path solves redundant rows by damped least squares
    if (nc_ == 0 || (sparse_ && static_cast<double>(nc_) * nv_ > kDenseSelectionEntries)) return;
    factor(t, "J M^-1 J^T");
    // a full-rank S needs nothing (sparse: every pivot above 1e-8 of its diagonal entry of S,
    // the dense path's threshold for its pseudo-inverse)
    if (rank_deficient_ || (sparse_ && sparse_gram_.least_relative_pivot() <= 1e-8)) reselect_dropped_rows(t);
}

// The left-out rows: the least independent rows of W = J Lm (S = W W^T), i.e. the last columns of
// a column-pivoted QR of W^T, so that the kept rows are as well conditioned as the greedy choice
// allows. Their number is fixed at the first selection (the rank deficiency of the assembled
// state). Returns whether the selection changed.
bool Augmented::reselect_dropped_rows(double t) {
    if (sparse_) {  // W with every row, densely (a selection is rare: at the start and on ill conditioning)
        sparse_gram_.fill(cv_.J, mass_inverse_);
        selection_W_ = sparse_gram_.W();
    }
    const Eigen::MatrixXd& W = sparse_ ? selection_W_ : dense_.form_W(cv_.J, mass_inverse_);
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(W.transpose());
    qr.setThreshold(1e-8);
    const int count = dropped_.empty() ? nc_ - static_cast<int>(qr.rank()) : static_cast<int>(dropped_.size());
    if (count <= 0) return false;
    std::vector<int> rows(qr.colsPermutation().indices().data() + (nc_ - count),
                          qr.colsPermutation().indices().data() + nc_);
    std::sort(rows.begin(), rows.end());
    if (rows == dropped_) return false;
    const bool first = dropped_.empty();
    keep_all_rows();
    dropped_ = rows;
    for (int r : dropped_) is_dropped_[r] = 1;
    std::string names;
    for (int r : dropped_) names += (names.empty() ? "" : ", ") + system_->describe_row(r);
    options_.log("augmented: t = " + format_time(t) + ": " + std::to_string(dropped_.size()) +
                 " redundant constraint row(s) " + (first ? "left out of" : "re-selected for") +
                 " the acceleration solve (multiplier 0): " + names);
    return true;
}

void Augmented::solve_dynamics(double t) {
    System& sys = *system_;
    refresh_mass(t, state_.q);
    sys.constraints_with_velocity_rows(state_, cv_, true);
    if (!redundancy_checked_) find_structural_redundancy(t);
    reaction_loads_.clear();  // Q_0: the reaction-loaded elements at N = 0
    sys.generalized_forces(state_, Q_);
    check_finite(t, Q_, "generalized forces");

    // gamma, with Baumgarte's terms when selected (book Sec. 6.12, L9420-9442)
    lambda_ = cv_.gamma;
    if (options_.stabilization == Stabilization::Baumgarte && nc_ > 0) {
        tmp_nc_.noalias() = cv_.J * state_.v;
        tmp_nc_ += cv_.C_t;
        const double a = options_.baumgarte_alpha, bb = options_.baumgarte_beta;
        lambda_ -= 2.0 * a * tmp_nc_;
        lambda_ -= bb * bb * cv_.C;
    }
    // keep the right-hand side gamma_s in vdot-space check below
    const double gamma_norm = nc_ ? lambda_.lpNorm<Eigen::Infinity>() : 0.0;
    b_ = lambda_;  // gamma_s
    solve_multipliers(t, gamma_norm);
    if (reaction_loads_.active()) solve_reaction_loads(t);
}

void Augmented::solve_reaction_loads(double t) {
    reaction_loads_.solve(t, state_, cv_.J, Q_, lambda_, [&](const Eigen::VectorXd& dQ, Eigen::VectorXd& dlambda) {
        apply_Minv(dQ, tmp_nv_);  // dlambda = S^-1 J M^-1 dQ: lambda's part linear in Q
        dlambda.noalias() = cv_.J * tmp_nv_;
        solve_S(dlambda);
    });
    tmp_nv2_.noalias() = cv_.J.transpose() * lambda_;
    tmp_nv2_ = Q_ - tmp_nv2_;
    apply_Minv(tmp_nv2_, vdot_);
    check_finite(t, vdot_, "accelerations");
}

void Augmented::solve_multipliers(double t, double gamma_norm) {
    // Schur complement: S lambda = J M^-1 Q - gamma_s (block inverse of Eq. 6.141, Eqs. 6.142-6.145)
    apply_Minv(Q_, tmp_nv_);
    if (nc_ == 0) {
        vdot_ = tmp_nv_;
        check_finite(t, vdot_, "accelerations");
        return;
    }
    // first the fast factorization; if the acceleration constraints then fail, once
    // more with the rank-revealing (dense) or damped least-squares (sparse) path
    double residual = std::numeric_limits<double>::infinity();
    for (int attempt = 0; attempt < 2; ++attempt) {
        factor(t, "J M^-1 J^T", attempt > 0);
        lambda_.noalias() = cv_.J * tmp_nv_;
        lambda_ -= b_;
        solve_S(lambda_);
        // vdot = M^-1 (Q - J^T lambda): Q_c = -J^T lambda (book Eq. 6.128)
        tmp_nv2_.noalias() = cv_.J.transpose() * lambda_;
        tmp_nv2_ = Q_ - tmp_nv2_;
        apply_Minv(tmp_nv2_, vdot_);
        // J vdot - gamma_s = b - S lambda: round-off after a well-conditioned Cholesky, dense or
        // sparse (every pivot above 1e-8 of its diagonal entry, the dense path's threshold for
        // its pseudo-inverse)
        const bool well_conditioned = sparse_ ? !rank_deficient_ && sparse_gram_.least_relative_pivot() > 1e-8
                                              : dense_.well_conditioned();
        if (well_conditioned && vdot_.allFinite() && lambda_.allFinite()) return;
        // the acceleration constraints must hold (J vdot = gamma_s, Eq. 6.139): this
        // catches a singular saddle point that the factorization did not flag
        if (vdot_.allFinite() && lambda_.allFinite()) {
            tmp_nc_.noalias() = cv_.J * vdot_;
            tmp_nc_ -= b_;
            double scale = 1.0 + gamma_norm;
            for (int c = 0; c < cv_.J.outerSize(); ++c)
                for (Eigen::SparseMatrix<double>::InnerIterator it(cv_.J, c); it; ++it)
                    scale = std::max(scale, std::abs(it.value() * vdot_[c]));
            // left-out rows hold on the motion (they depend on the others there); off it, at the
            // integrator's stage states, they need not: project() checks them on the motion
            for (int r : dropped_) tmp_nc_[r] = 0.0;
            residual = tmp_nc_.lpNorm<Eigen::Infinity>() / scale;
            // the fast path must solve Eq. 6.139 to round-off; the rank-revealing path gives
            // the least-squares accelerations, which leave a residual only in the dependent
            // directions (redundant constraints are consistent on the motion, and off it by
            // the integrator's local error): accept that, but not an O(1) inconsistency
            // (a singular configuration where the mechanism locks or bifurcates)
            if (residual <= (rank_deficient_ ? 1e-2 : 1e-6)) return;
        }
        if (rank_deficient_) break;  // the robust path was already taken
    }
    char detail[96];
    std::snprintf(detail, sizeof detail, "J vdot = gamma has no solution, relative residual %.2g", residual);
    redundant_rows_error(t, detail);
}

void Augmented::rhs(double t, const Eigen::VectorXd& y, Eigen::VectorXd& ydot) {
    from_ode(t, y, state_);
    if (!y.allFinite()) throw NonFiniteMotion(t, "non-finite state: the motion diverged (try a smaller tolerance or step)");
    solve_dynamics(t);
    ydot.resize(nq_ + nv_);
    if (planar_) {
        ydot.head(nq_) = state_.v;
    } else {
        // Rdot = v_R, pdot = 1/2 Gbar^T wbar (book Eq. 8.48 with Gbar of Eq. 8.44)
        for (int b = 0; b < nb_; ++b) {
            const int iq = 7 * b, iv = 6 * b;
            ydot.segment<3>(iq) = state_.v.segment<3>(iv);
            const Vec4 p = state_.q.segment<4>(iq + 3);
            ydot.segment<4>(iq + 3).noalias() = 0.5 * euler_Gbar(p).transpose() * state_.v.segment<3>(iv + 3);
        }
        const int flexible = system_->flexible_coordinates();  // v = qdot, after the rigid blocks
        ydot.segment(nq_ - flexible, flexible) = state_.v.tail(flexible);
    }
    ydot.tail(nv_) = vdot_;
}

bool Augmented::project(double t, Eigen::VectorXd& y) {
    System& sys = *system_;
    from_ode(t, y, state_);
    sys.normalize(state_.q);  // unit Euler parameters
    if (options_.stabilization != Stabilization::Projection || nc_ == 0) {
        y.head(nq_) = state_.q;
        if (singularity_.active(sys)) {
            sys.constraints_with_velocity_rows(state_, cv_, true);
            singularity_.check(sys, t, cv_.J);
        }
        return true;
    }
    // Newton on C(q, t) = 0 with steps of least kinetic-energy norm, then the velocity
    // projection (shared with the amalgamated formulation: kit/include/mbd/kit/projection.hpp),
    // with this formulation's factorization of S = J M^-1 J^T (fast first, then robust)
    projection_.q0 = y.head(nq_);
    projection_.v0 = y.tail(nv_);
    refresh_mass(t, state_.q);  // the metric at the step's positions
    const bool ok = project_onto_constraints(
        sys, t, projection_, options_.projection_tolerance, state_, cv_,
        [&](bool robust) { factor(t, "projection", robust); }, [&](Eigen::VectorXd& x) { solve_S(x); },
        [&](const Eigen::VectorXd& x, Eigen::VectorXd& out) { apply_Minv(x, out); });
    if (!ok) return false;
    if (!dropped_.empty() && !left_out_rows_hold()) {
        // on the motion a left-out row must hold by itself; it does not: it is no longer redundant
        options_.log("augmented: t = " + format_time(t) +
                     ": a left-out constraint row is no longer redundant; every row is used again");
        keep_all_rows();
        return project(t, y);
    }
    // cv_ is at the projected positions, where the velocity projection last factored S
    singularity_.check(sys, t, cv_.J, last_relative_pivot());
    y.head(nq_) = state_.q;
    y.tail(nv_) = state_.v;
    return true;
}

void Augmented::solve_at(const State& state) {
    state_.t = state.t;
    state_.q = state.q;
    state_.v = state.v;
    solve_dynamics(state.t);
}

void Augmented::multipliers(const State& state, Eigen::VectorXd& lambda) {
    solve_at(state);
    lambda = lambda_;
}

void Augmented::accelerations(const State& state, Eigen::VectorXd& vdot) {
    solve_at(state);
    vdot = vdot_;
}

}  // namespace

std::unique_ptr<Formulation> make_augmented(const FormulationSpec&) { return std::make_unique<Augmented>(); }

}  // namespace mbd

MBD_FORMULATION_PLUGIN(augmented, mbd::make_augmented)
