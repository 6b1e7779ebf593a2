// The Hamiltonian formulation (Shabana, Computational Dynamics, Sec. 5.10, Eqs. 5.165-5.182),
// EMBEDDED on the independent coordinates of a coordinate partition (the embedding
// technique's velocity transformation, book Sec. 6.5, kit velocity_transform.hpp), so that
// closed loops, drivers and redundant rows work as in the embedding formulation's dense path.
//
// Partition of J (partition.hpp): v = B v_i + c (B_i = I, B_d = -J_d^-1 J_i, c_d = -J_d^-1 C_t).
// With T = 1/2 v^T M v, the momenta conjugate to the independent velocities are
//     p = dT/dv_i = B^T M v = Mbar v_i + B^T M c,      Mbar = B^T M B  (SPD)
//     H(q, p, t) = p^T v_i - T + V = 1/2 (p - B^T M c)^T Mbar^-1 (p - B^T M c) - 1/2 c^T M c + V
// (scleronomic, c = 0: H = 1/2 p^T Mbar^-1 p + V = T + V, book Eq. 5.182). Hamilton's
// equations (Eq. 5.179):
//     qdot_i = dH/dp = Mbar^-1 (p - B^T M c) = v_i     (the dependent rates follow, v = B v_i + c)
//     pdot   = -dH/dq_i + Q_nc = B^T Q + Bdot^T M v
// The second form is the same quantity evaluated without differentiating Mbar: p = B^T M v,
// pdot = B^T M vdot + Bdot^T M v and B^T (M vdot - Q) = B^T Q_c = 0 (Eq. 4.19); for
// coordinates whose rates are the velocity components (planar bodies) dT/dq_i|_{qdot_i} =
// Bdot^T M v by the symmetry of second derivatives, so B^T Q + Bdot^T M v = -dH/dq_i + Q_nc
// exactly (Q = Q_nc - dV/dq). For spatial bodies the angular components are body-axis
// angular velocities (quasi-velocities) and p are the conjugate quasi-momenta (Hamel /
// Poincare form); the same expression holds with Q carrying the gyroscopic term.
//
// Bdot without second derivatives of the joints: from J B = 0 on the kept rows,
// J_d Bdot_d = -(Jdot B), so Bdot^T M v = -(Jdot B)^T mu = -B^T (Jdot^T mu) with
// mu = J_d^-T (M v)_d (zero on the rows left out). Jdot^T mu follows exactly from gamma
// (quadratic in v; Cddot = J vdot - gamma): the joints' own (d gamma / d v)^T mu where they give
// it, a coloured polarization of gamma otherwise, plus the Lie bracket of the body-axis
// angular velocities of spatial bodies (kit jdot_transpose.hpp), on both paths.
//
// Sparse path (above the sparse threshold, coordinate_selector.hpp): B is never formed (it is
// dense, n_v x k, in absolute coordinates; B^T M B is dense k x k on a chain). The velocities
// follow from p through the saddle-point system of the kept rows,
//     M v - J^T mu = E_i p,   J v = -C_t        (E_i p: p at the independent components)
// whose first rows give B^T M v = p (multiply by B^T: B^T J^T = 0, B^T E_i = I) and whose
// dependent rows give mu = J_d^-T (M v)_d, the mu of Bdot^T M v above; it is solved through the
// sparse S = J M^-1 J^T (sparse_gram.hpp): S mu = -C_t - J M^-1 E_i p, v = M^-1 (E_i p + J^T mu).
// Then pdot = B^T (Q - Jdot^T mu) with B^T x = x_i - J_i^T J_d^-T x_d through a sparse LU of J_d
// (sparse_velocity_transform.hpp) and Jdot^T mu as above: O(n) per rhs.
// With few freedoms (k <= kFewFreedoms) the velocities come instead from the k columns of B
// and the k x k Mbar, each column one solve with J_d's LU, as on the dense path: S's condition
// is J's squared, and where J itself loses rank (IFToMM A02's 40 four-bars at their dead
// points, 40 rows at once) S-based velocities lost their digits and dopri5 stalled, while a
// re-selected J_d stays as usable as on the dense path. mu is then J_d^-T (M v)_d directly.
// Momentum scale on that path: diag(M) at the independent components (diag(Mbar) needs all of
// B; diag(M) <= diag(Mbar) for diagonal body blocks, so the state's momenta are at least as
// large as in velocity units and the absolute tolerance no looser).
//
// ODE state y = [q; p / m] (all coordinates; the k momenta, each divided by the diagonal
// entry m_j of Mbar when the partition was selected, so that the state holds them in
// velocity units). The integrators' tolerances are relative plus absolute (atol = rtol =
// tol): a momentum of a light, small mechanism (Andrews' squeezer: |p| ~ 1e-2 N m s) would
// otherwise be controlled by the absolute part only, i.e. 100 times more loosely than the
// velocities of the other formulations, and the results lost two digits at every tolerance.
// After each accepted step the
// dependent positions are corrected by Newton-Raphson holding the independent directions
// (as the embedding formulation); the velocity constraints hold by construction. Near a
// singular J_d the partition is re-selected at the end of an accepted step and p rewritten
// as B_new^T M v (the same velocities).
#include <mbd/kit/non_finite_motion.hpp>
#include <mbd/kit/coordinate_rates.hpp>
#include <mbd/kit/formulation.hpp>
#include <mbd/kit/partition.hpp>
#include <mbd/kit/partition_settings.hpp>
#include <mbd/kit/singularity.hpp>
#include <mbd/sdk/text.hpp>
#include <mbd/kit/velocity_transform.hpp>

#include <mbd/kit/coordinate_selector.hpp>
#include <mbd/kit/partition_switch.hpp>
#include <mbd/kit/jdot_transpose.hpp>
#include <mbd/kit/rank_certificate.hpp>
#include <mbd/kit/sparse_gram.hpp>
#include <mbd/kit/sparse_velocity_transform.hpp>

#include <mbd/kit/block_mass_inverse.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

namespace mbd {
namespace {

class Hamiltonian final : public Formulation {
public:
    Hamiltonian() = default;

    MBD_FORMULATION_CALLS;
    MBD_FORMULATION_STATE_CONVERSIONS;
    int ode_size() const override { return nq_ + static_cast<int>(part_.independent.size()); }
    bool state_redefined() override {
        const bool r = redefined_;
        redefined_ = false;
        return r;
    }
    bool has_hamiltonian() const override { return true; }
    double hamiltonian(double t, const Eigen::VectorXd& y) override;
    OptionGroups options_used() const override { return kPartitionOptions | kNewtonOptions | kSingularityOptions; }

private:
    void select(const State& state, bool initial);
    // cv_, J_ at (t, q) with v = 0; B_, c_ for the partition
    void transform(double t, const Eigen::VectorXd& q);
    // transform(), then v_i and v from p: state_ holds (t, q, v)
    void kinematics(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& p);
    // kinematics() at y's q and momenta (copied into q_, p_)
    void kinematics(double t, const Eigen::VectorXd& y);
    // the constraints at a state and a partition valid there (re-selected when near singular)
    CoordinatePartition partition_at(const State& state);
    // vdot at a state for partition p (and Q_ there)
    void solve_accelerations(double t, const CoordinatePartition& p, const State& state, Eigen::VectorXd& vdot);
    // the momenta p from the state's scaled momenta, and back (see the header)
    void momenta(const Eigen::VectorXd& y, Eigen::VectorXd& p) const {
        p = y.tail(momentum_scale_.size()).cwiseProduct(momentum_scale_);
    }
    void store_momenta(const Eigen::VectorXd& p, Eigen::VectorXd& y) const {
        y.tail(momentum_scale_.size()) = p.cwiseQuotient(momentum_scale_);
    }
    // momentum_scale_ = diag(Mbar) at q, for the current partition
    void set_momentum_scale(double t, const Eigen::VectorXd& q);
    // sparse path: the kept rows' S = J M^-1 J^T at cv_.J (redundant rows decoupled)
    void factor_gram(double t);
    // sparse path: v and mu (the kept rows' multipliers) from p at the J, C_t of transform()
    void sparse_velocities(const Eigen::VectorXd& p);
    // Mbar = B^T M B from B_ and its Cholesky (dense path, and the sparse one with few freedoms)
    void factor_mbar(double t);
    // v_i and v from p through B_, c_ and Mbar's Cholesky (qdot_i = dH/dp, Eq. 5.179)
    void velocities_through_b(const Eigen::VectorXd& p);
    // sparse path with few freedoms: the same through B's k columns and Mbar (see the header)
    void few_freedom_velocities(const Eigen::VectorXd& p);
    static constexpr size_t kFewFreedoms = 16;
    bool few_freedoms_ = false;  // sparse_ and k <= kFewFreedoms
    // dense path: the pivot ratio of J_d for partition p at J (complete pivoting of the gathered J_d)
    double pivot_ratio(const Eigen::MatrixXd& J_dense, const CoordinatePartition& p);
    // sparse path: vdot and the multipliers at a state from the kept rows' saddle-point system
    // (M vdot + J^T lambda = Q, J vdot = gamma): the embedded equations' solution, Eq. 6.95
    void sparse_accelerations(const State& state, Eigen::VectorXd& vdot, Eigen::VectorXd& lambda);
    bool sparse_ = false;  // selector_.sparse(): B never formed (see the header)

    PartitionSettings partition_settings_;
    bool log_choices_ = false;              // FormulationOptions::log_choices, default false
    SingularityMonitor singularity_;        // rank drop of J after an accepted step (singularity.hpp)
    RankCertificate rank_certificate_;      // lent to singularity_ (support/rank_certificate.hpp)
    NewtonSettings newton_;

    System* system_ = nullptr;
    int nq_ = 0, nv_ = 0, nc_ = 0;
    const Eigen::SparseMatrix<double>* M_ = nullptr;  // the System's M (block diagonal): M B in O(n_v k)
    MessageLog log_;  // FormulationOptions::log
    CoordinatePartition part_;
    Eigen::VectorXd momentum_scale_;  // diag(Mbar) at the selection: p = momentum_scale_ .* y_p
    bool selected_ = false;
    bool redefined_ = false;  // set by a re-selection in project(), cleared by state_redefined()
    double last_rhs_t_ = -std::numeric_limits<double>::infinity();

    // scratch, sized in bind() or by the first evaluation: rhs() and project() allocate nothing
    State state_, corrected_;
    ConstraintValues cv_, cv_corrected_;
    Eigen::MatrixXd J_, J_corrected_, B_, MB_, Mbar_;
    Eigen::VectorXd c_, vi_, gamma_prime_, Q_, q_, p_, zero_, Mx_, Bx_, pdot_, b_, mu_, mu_rows_, jw_;
    Eigen::LLT<Eigen::MatrixXd> llt_;                // of Mbar
    VelocityTransformWorkspace transform_;
    CoordinateSelector selector_;     // dense or sparse by size (coordinate_selector.hpp)
    CoordinatePartition fresh_;
    Eigen::VectorXd v_before_;
    // sparse path
    BlockMassInverse mass_inverse_;
    SparseGram gram_;
    SparseVelocityTransform sparse_transform_;
    PartitionSwitch switch_;  // to a re-selected partition, keeping the one left
    JdotTranspose jdot_;
    bool probe_columns_ = false;  // dense path: Jdot B column by column (fewer probes than jdot_'s groups)
    std::vector<char> redundant_;  // per row: dropped by the partition
    Eigen::VectorXd u_, w_, jt_mu_, unit_, no_rates_, column_;
};

void Hamiltonian::bind(System& system, const FormulationOptions& options) {
    system_ = &system;
    log_ = options.log;
    partition_settings_ = options.partition;
    log_choices_ = options.log_choices.value_or(false) && options.log.enabled();  // no text built for nobody
    newton_ = options.newton;
    singularity_.tolerance = options.singularity_tolerance;
    nq_ = system.nq();
    nv_ = system.nv();
    nc_ = system.constraint_rows(true);
    M_ = &system.mass_matrix();
    selected_ = false;
    redefined_ = false;
    singularity_.reset();
    rank_certificate_.bind(system, singularity_);
    last_rhs_t_ = -std::numeric_limits<double>::infinity();
    state_.set_zero(nq_, nv_);
    Q_.setZero(nv_);
    Mx_.setZero(nv_);
    v_before_.setZero(nv_);
    selector_.bind(nc_, nv_, options, fresh_);  // a re-selection allocates nothing (dense)
    corrected_.q.setZero(nq_);
    corrected_.v.setZero(nv_);
    sparse_ = selector_.sparse();
    jdot_.bind(system);
    mu_rows_.setZero(nc_);
    if (sparse_) {
        mass_inverse_.bind(system, "hamiltonian formulation");
        if (nc_ > 0) gram_.analyze(system);
        u_.setZero(nv_);
        w_.setZero(nv_);
        mu_.setZero(nc_);
        b_.setZero(nc_);
    }
    select(assembled_initial_state(system), true);
}

void Hamiltonian::select(const State& state, bool initial) {
    system_->constraints(state, cv_, true);
    if (!sparse_) J_ = cv_.J;
    part_ = selector_.select(cv_.J, initial ? partition_settings_.pivot_threshold : 1.0, partition_settings_.rank_tolerance);
    selected_ = true;
    few_freedoms_ = sparse_ && part_.independent.size() <= kFewFreedoms;
    // 2 k gamma evaluations column by column against 2 per group of jdot_'s colouring
    probe_columns_ = static_cast<int>(part_.independent.size()) < jdot_.groups();
    if (sparse_) {
        sparse_transform_.select(cv_.J, part_);
        switch_.reset();
        redundant_.assign(nc_, 0);
        for (int r : part_.redundant) redundant_[r] = 1;
    }
    set_momentum_scale(state.t, state.q);
    if (initial && !part_.redundant.empty())
        log_("hamiltonian: " + redundant_rows_message(part_, [&](int r) { return system_->describe_row(r); }));
}

void Hamiltonian::set_momentum_scale(double t, const Eigen::VectorXd& q) {
    transform(t, q);
    if (!sparse_) {
        momentum_scale_ = Mbar_.diagonal();  // positive: Mbar is positive definite
        return;
    }
    momentum_scale_.resize(static_cast<Eigen::Index>(part_.independent.size()));
    for (size_t c = 0; c < part_.independent.size(); ++c)
        momentum_scale_[c] = M_->coeff(part_.independent[c], part_.independent[c]);  // see the header
}

void Hamiltonian::factor_gram(double t) {
    if (nc_ == 0) return;
    gram_.fill(cv_.J, mass_inverse_, &redundant_);
    if (!gram_.factor(0.0))
        throw DynamicsError(t, "hamiltonian: the kept constraint rows are dependent here (J M^-1 J^T is singular at " +
                                   system_->describe_row(gram_.failed_row()) + ")");
}

void Hamiltonian::sparse_velocities(const Eigen::VectorXd& p) {
    if (few_freedoms_) {
        few_freedom_velocities(p);
        return;
    }
    // M v - J^T mu = E_i p, J v = -C_t (see the header)
    w_.setZero();
    for (size_t c = 0; c < part_.independent.size(); ++c) w_[part_.independent[c]] = p[c];
    mu_.setZero();
    if (nc_ > 0) {
        mass_inverse_.apply(w_, u_);
        b_.noalias() = cv_.J * u_;
        mu_ = -cv_.C_t - b_;
        for (int r : part_.redundant) mu_[r] = 0.0;
        gram_.solve(mu_, 0);
        w_.noalias() += cv_.J.transpose() * mu_;
    }
    mass_inverse_.apply(w_, state_.v);
    vi_.resize(static_cast<Eigen::Index>(part_.independent.size()));
    for (size_t c = 0; c < part_.independent.size(); ++c) vi_[c] = state_.v[part_.independent[c]];
}

void Hamiltonian::transform(double t, const Eigen::VectorXd& q) {
    state_.t = t;
    state_.q = q;
    state_.v.setZero(nv_);
    system_->constraints(state_, cv_, true);  // J and C_t do not depend on v
    if (sparse_) {
        if (!sparse_transform_.factor(cv_.J))
            throw DynamicsError(t, "hamiltonian: the dependent sub-Jacobian J_d is singular");
        if (!few_freedoms_) factor_gram(t);
        return;
    }
    J_ = cv_.J;
    if (!velocity_transform(J_, cv_.gamma, part_, B_, gamma_prime_, transform_))
        throw DynamicsError(t, "hamiltonian: the dependent sub-Jacobian J_d is singular");
    // c = v for v_i = 0: c_d = -J_d^-1 C_t on the kept rows, with velocity_transform's LU of J_d
    c_.setZero(nv_);
    if (part_.rank > 0) {
        gather(cv_.C_t, part_.rows, transform_.b);
        transform_.x = transform_.lu.solve(transform_.b);
        for (int i = 0; i < part_.rank; ++i) c_[part_.dependent[i]] = -transform_.x[i];
    }
    factor_mbar(t);
}

void Hamiltonian::factor_mbar(double t) {
    MB_.noalias() = *M_ * B_;
    Mbar_.noalias() = B_.transpose() * MB_;
    if (B_.cols() > 0) {
        llt_.compute(Mbar_);
        if (llt_.info() != Eigen::Success) throw DynamicsError(t, "hamiltonian: B^T M B is not positive definite");
    }
}

void Hamiltonian::velocities_through_b(const Eigen::VectorXd& p) {
    // qdot_i = dH/dp = Mbar^-1 (p - B^T M c), v = B v_i + c
    if (B_.cols() > 0) {
        Mx_.noalias() = *M_ * c_;
        Bx_.noalias() = B_.transpose() * Mx_;
        Bx_ = p - Bx_;
        vi_ = llt_.solve(Bx_);
    } else {
        vi_.resize(0);
    }
    state_.v.noalias() = B_ * vi_;
    state_.v += c_;
}

void Hamiltonian::kinematics(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& p) {
    transform(t, q);
    if (sparse_) {
        sparse_velocities(p);
        return;
    }
    velocities_through_b(p);
}

void Hamiltonian::few_freedom_velocities(const Eigen::VectorXd& p) {
    // v = B v_i + c (Eq. 6.169), B and c through J_d's LU; Mbar v_i = p - B^T M c
    const int k = static_cast<int>(part_.independent.size());
    zero_.setZero(k);
    sparse_transform_.velocities(cv_.J, cv_.C_t, zero_, c_);
    no_rates_.setZero(nc_);
    B_.resize(nv_, k);
    for (int j = 0; j < k; ++j) {
        unit_.setZero(k);
        unit_[j] = 1.0;
        sparse_transform_.velocities(cv_.J, no_rates_, unit_, column_);
        B_.col(j) = column_;
    }
    factor_mbar(state_.t);
    velocities_through_b(p);
    Mx_.noalias() = *M_ * state_.v;
    sparse_transform_.dependent_multipliers(Mx_, mu_);  // mu = J_d^-T (M v)_d
}

void Hamiltonian::kinematics(double t, const Eigen::VectorXd& y) {
    q_ = y.head(nq_);
    momenta(y, p_);
    kinematics(t, q_, p_);
}

void Hamiltonian::to_ode(const State& state, Eigen::VectorXd& y) {
    if (!selected_) select(state, true);
    transform(state.t, state.q);
    const int k = static_cast<int>(part_.independent.size());
    y.resize(nq_ + k);
    y.head(nq_) = state.q;
    if (sparse_) {
        Mx_.noalias() = *M_ * state.v;
        sparse_transform_.transpose_times(cv_.J, Mx_, Bx_);
        store_momenta(Bx_, y);
        return;
    }
    store_momenta(B_.transpose() * (*M_ * state.v), y);  // p = B^T M v
}

void Hamiltonian::from_ode(double t, const Eigen::VectorXd& y, State& state) {
    kinematics(t, y);
    state.t = t;
    state.q = state_.q;
    state.v = state_.v;
}

double Hamiltonian::hamiltonian(double t, const Eigen::VectorXd& y) {
    kinematics(t, y);
    // H = p^T qdot_i - L = p^T v_i - T + V (= T + V when scleronomic)
    return p_.dot(vi_) - system_->kinetic_energy(state_) + system_->potential_energy(state_);
}

void Hamiltonian::rhs(double t, const Eigen::VectorXd& y, Eigen::VectorXd& ydot) {
    if (!y.allFinite()) throw NonFiniteMotion(t, "non-finite state: the motion diverged (try a smaller tolerance or step)");
    last_rhs_t_ = t;
    const int k = static_cast<int>(part_.independent.size());
    kinematics(t, y);
    system_->generalized_forces(state_, Q_);
    if (!Q_.allFinite()) throw NonFiniteMotion(t, "non-finite generalized forces: the motion diverged");
    ydot.resize(nq_ + k);
    write_coordinate_rates(system_->dimension(), state_.q, state_.v, ydot.head(nq_));  // from qdot_i = dH/dp
    if (k == 0) return;
    if (sparse_) {
        // pdot = B^T (Q - Jdot^T mu), mu from sparse_velocities() (see the header)
        if (part_.rank > 0) {
            jdot_.apply(*system_, state_, cv_.J, mu_, jt_mu_);
            Q_ -= jt_mu_;
        }
        sparse_transform_.transpose_times(cv_.J, Q_, pdot_);
        if (!pdot_.allFinite()) throw NonFiniteMotion(t, "non-finite momentum rates: the motion diverged");
        ydot.tail(k) = pdot_.cwiseQuotient(momentum_scale_);
        return;
    }
    // pdot = -dH/dq_i + Q_nc = B^T Q + Bdot^T M v,  Bdot^T M v = -(Jdot B)^T mu
    pdot_.noalias() = B_.transpose() * Q_;
    if (part_.rank > 0) {
        Mx_.noalias() = *M_ * state_.v;
        gather(Mx_, part_.dependent, b_);
        // mu = J_d^-T (M v)_d with transform()'s LU of J_d (P J_d = L U: J_d^-T = P^T L^-T U^-T),
        // written out: Eigen's transposed solve allocates a temporary
        const auto& LU = transform_.lu.matrixLU();
        LU.triangularView<Eigen::Upper>().transpose().solveInPlace(b_);
        LU.triangularView<Eigen::UnitLower>().transpose().solveInPlace(b_);
        mu_.noalias() = transform_.lu.permutationP().transpose() * b_;
        // -(Jdot B)^T mu = -B^T (Jdot^T mu), mu zero on the rows left out of the partition
        mu_rows_.setZero();
        for (size_t r = 0; r < part_.rows.size(); ++r) mu_rows_[part_.rows[r]] = mu_[static_cast<Eigen::Index>(r)];
        if (probe_columns_) {
            for (int c = 0; c < k; ++c) {
                jdot_.times(*system_, state_, cv_.J, B_.col(c), jw_);
                pdot_[c] -= mu_rows_.dot(jw_);
            }
        } else {
            jdot_.apply(*system_, state_, cv_.J, mu_rows_, jt_mu_);
            pdot_.noalias() -= B_.transpose() * jt_mu_;
        }
    }
    if (!pdot_.allFinite()) throw NonFiniteMotion(t, "non-finite momentum rates: the motion diverged");
    ydot.tail(k) = pdot_.cwiseQuotient(momentum_scale_);
}

bool Hamiltonian::project(double t, Eigen::VectorXd& y) {
    System& sys = *system_;
    State& s = corrected_;
    ConstraintValues& cv = cv_corrected_;
    Eigen::MatrixXd& J = J_corrected_;
    s.t = t;
    s.q = y.head(nq_);
    s.v.setZero(nv_);
    sys.normalize(s.q);
    const double tol = newton_.tolerance * std::max(1.0, s.q.lpNorm<Eigen::Infinity>());
    if (sparse_) {
        const bool converged = correct_dependent_positions_with(
            sys, s, part_, tol, newton_.iterations, cv, transform_.dv, [&](const ConstraintValues& at, Eigen::VectorXd& dv) {
                b_ = -at.C;
                return sparse_transform_.factor(at.J) && sparse_transform_.solve_dependent(b_, dv);
            });
        if (!converged) return false;
    } else if (!correct_dependent_positions(sys, s, part_, tol, newton_.iterations, cv, J, transform_)) {
        return false;
    }
    singularity_.check(sys, t, cv.J);  // cv at the corrected positions
    // re-selection near a singular J_d (book Sec. 6.12), only at the end of an accepted step.
    // B = -J_d^-1 J_i grows as J_d approaches singularity, and with it the local error of a
    // fixed-step method (rk4 on the conservative four-bar: the energy error per step grew from
    // 1e-11 to 1.4e-7 in the steps before a switch at pivot ratio reselect_ratio = 0.05). So
    // below 10 x reselect_ratio a fresh selection is compared with the current one, and taken
    // as soon as its pivot ratio is twice as good (below reselect_ratio: as soon as it is
    // better); the factor 2 keeps the two selections from alternating.
    if (t >= last_rhs_t_ && part_.rank > 0) {
        // the trigger: dense, J_d's complete-pivoting ratio; sparse, its LU's ratio relative to
        // the one the partition was chosen at (the LU's partial pivots carry the rows' geometric
        // scale, sparse_velocity_transform.hpp)
        const double ratio = sparse_ ? (sparse_transform_.factor(cv.J) ? sparse_transform_.relative_pivot_ratio() : 0.0)
                                     : pivot_ratio(J, part_);
        if (ratio < 10.0 * partition_settings_.reselect_ratio) {
            momenta(y, p_);
            kinematics(t, s.q, p_);
            v_before_ = state_.v;
            CoordinatePartition& fresh = fresh_;
            selector_.select(cv.J, 1.0, partition_settings_.rank_tolerance, {}, fresh);
            if (fresh.rank != part_.rank)
                throw DynamicsError(t, "hamiltonian: singular configuration, the constraint Jacobian has rank " +
                                           std::to_string(fresh.rank) + " instead of " + std::to_string(part_.rank));
            // the two partitions compared like with like (coordinate_selector.hpp; the trigger's
            // relative ratio is no measure of another partition)
            const double current =
                sparse_ ? selector_.dependent_pivot_ratio(cv.J, part_, partition_settings_.rank_tolerance) : ratio;
            const double candidate = sparse_ ? selector_.dependent_pivot_ratio(cv.J, fresh, partition_settings_.rank_tolerance)
                                             : pivot_ratio(J, fresh);
            const double gain = ratio < partition_settings_.reselect_ratio ? 1.0 : 2.0;
            if (!same_set(fresh.dependent, part_.dependent) && candidate > gain * current) {
                const Eigen::VectorXd& v = v_before_;
                if (sparse_) {
                    switch_.to(cv.J, fresh, part_, sparse_transform_);
                    redundant_.assign(nc_, 0);
                    for (int r : part_.redundant) redundant_[r] = 1;
                } else {
                    part_ = fresh;
                }
                set_momentum_scale(t, s.q);
                Mx_.noalias() = *M_ * v;  // the same velocities in the new momenta
                if (sparse_)
                    sparse_transform_.transpose_times(cv_.J, Mx_, Bx_);
                else
                    Bx_.noalias() = B_.transpose() * Mx_;
                store_momenta(Bx_, y);
                redefined_ = true;
                if (log_choices_) log_("hamiltonian: t = " + format_time(t) + ": new coordinate partition");
            }
        }
    }
    y.head(nq_) = s.q;
    return true;
}

double Hamiltonian::pivot_ratio(const Eigen::MatrixXd& J_dense, const CoordinatePartition& p) {
    return dependent_pivot_ratio(J_dense, p, transform_);
}

void Hamiltonian::sparse_accelerations(const State& state, Eigen::VectorXd& vdot, Eigen::VectorXd& lambda) {
    system_->constraints(state, cv_, true);
    system_->generalized_forces(state, Q_);
    lambda.setZero(nc_);
    if (nc_ > 0) {
        factor_gram(state.t);
        // S lambda = J M^-1 Q - gamma (the kept rows; dropped rows get 0)
        mass_inverse_.apply(Q_, u_);
        lambda.noalias() = cv_.J * u_;
        lambda -= cv_.gamma;
        for (int r : part_.redundant) lambda[r] = 0.0;
        gram_.solve(lambda, 0);
    }
    w_ = Q_;
    if (nc_ > 0) w_.noalias() -= cv_.J.transpose() * lambda;
    vdot.resize(nv_);
    mass_inverse_.apply(w_, vdot);
}

void Hamiltonian::solve_accelerations(double t, const CoordinatePartition& p, const State& state,
                                      Eigen::VectorXd& vdot) {
    system_->constraints(state, cv_, true);
    J_ = cv_.J;
    system_->generalized_forces(state, Q_);
    Eigen::MatrixXd B;
    Eigen::VectorXd g;
    if (!velocity_transform(J_, cv_.gamma, p, B, g, transform_))
        throw DynamicsError(t, "hamiltonian: the dependent sub-Jacobian J_d is singular");
    const Eigen::MatrixXd MB = *M_ * B;
    const Eigen::MatrixXd Mbar = B.transpose() * MB;
    Eigen::VectorXd vdot_i(B.cols());
    if (B.cols() > 0) vdot_i = Mbar.llt().solve(B.transpose() * (Q_ - *M_ * g));
    vdot = B * vdot_i + g;
}

// The constraints at `state` (J_, cv_) and a partition valid there: the current one, or a
// fresh choice when its dependent block is near singular.
CoordinatePartition Hamiltonian::partition_at(const State& state) {
    system_->constraints(state, cv_, true);
    J_ = cv_.J;
    CoordinatePartition p = part_;
    if (dependent_pivot_ratio(J_, p, transform_) < partition_settings_.reselect_ratio) p = selector_.select(cv_.J, 1.0, partition_settings_.rank_tolerance);
    return p;
}

void Hamiltonian::accelerations(const State& state, Eigen::VectorXd& vdot) {
    if (sparse_) {
        sparse_accelerations(state, vdot, b_);
        return;
    }
    solve_accelerations(state.t, partition_at(state), state, vdot);
}

void Hamiltonian::multipliers(const State& state, Eigen::VectorXd& lambda) {
    if (sparse_) {
        sparse_accelerations(state, Mx_, lambda);
        return;
    }
    const CoordinatePartition p = partition_at(state);
    Eigen::VectorXd vdot;
    solve_accelerations(state.t, p, state, vdot);
    multipliers_from_dependent_rows(J_, p, Eigen::VectorXd(Q_ - *M_ * vdot), lambda, transform_);
}

}  // namespace

std::unique_ptr<Formulation> make_hamiltonian(const FormulationSpec&) { return std::make_unique<Hamiltonian>(); }

}  // namespace mbd

MBD_FORMULATION_PLUGIN(hamiltonian, mbd::make_hamiltonian)
