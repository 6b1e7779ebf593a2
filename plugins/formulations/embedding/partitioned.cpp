// The dense path of the embedding formulation: see partitioned.hpp.
#include "partitioned.hpp"

#include <mbd/kit/non_finite_motion.hpp>
#include <mbd/kit/coordinate_rates.hpp>
#include <mbd/sdk/text.hpp>  // format_time

#include <algorithm>
#include <cmath>
#include <iostream>
#include <set>

namespace mbd::embedding {

namespace {
// Names of the velocity components: planar body.x, body.y, body.angle; spatial body.x,
// body.y, body.z (mass-centre velocity, world) and body.wx, body.wy, body.wz (angular
// velocity in body axes).
std::vector<std::string> velocity_names(System& system) {
    static const char* planar[] = {"x", "y", "angle"};
    static const char* spatial[] = {"x", "y", "z", "wx", "wy", "wz"};
    const bool is_planar = system.dimension() == Dimension::Planar;
    std::vector<std::string> names;
    for (int b = 0; b < system.body_count(); ++b)
        for (int c = 0; c < (is_planar ? 3 : 6); ++c)
            names.push_back(system.body(b).name + "." + (is_planar ? planar[c] : spatial[c]));
    return names;
}
}  // namespace

void Partitioned::bind(System& system, const FormulationOptions& options) {
    system_ = &system;
    options_ = options;
    log_choices_ = options.log_choices.value_or(true) && options.log.enabled();  // no text built for nobody
    nq_ = system.nq();
    nv_ = system.nv();
    nc_ = system.constraint_rows(true) + system.velocity_constraint_rows();
    names_ = velocity_names(system);
    M_ = &system.mass_matrix();
    selected_ = false;
    reselections_ = 0;
    redefined_ = false;
    last_rhs_t_ = -std::numeric_limits<double>::infinity();
    state_.set_zero(nq_, nv_);
    Q_.setZero(nv_);
    v_before_.setZero(nv_);
    selector_.bind(nc_, nv_, options, fresh_);  // a re-selection allocates nothing (dense)
    vdot_.setZero(nv_);
    // The ODE size needs the rank: select at the assembled initial state.
    select(assembled_initial_state(system), true);
}

int Partitioned::ode_size() const { return nq_ + nv_ - part_.rank; }

std::string Partitioned::independent_names() const {
    std::string out;
    for (int c : part_.independent) out += (out.empty() ? "" : ", ") + names_[c];
    return out.empty() ? std::string("(none)") : out;
}

void Partitioned::log_partition(double t, const char* what) const {
    if (log_choices_) options_.log("embedding: t = " + format_time(t) + ": independent coordinates " + what + independent_names());
}

void Partitioned::evaluate(const State& state) {
    system_->constraints_with_velocity_rows(state, cv_, true);  // the joints' A v = b rows partitioned alike
    J_ = cv_.J;  // in place
}

void Partitioned::select(const State& state, bool initial) {
    evaluate(state);
    if (initial && !independent_.empty()) {
        // the requested independent components last, with a tiny threshold: they stay
        // independent whenever the others can form a nonsingular J_d
        std::vector<int> last;
        for (const std::string& name : independent_) {
            const auto it = std::find(names_.begin(), names_.end(), name);
            if (it == names_.end())
                throw InputError("", "embedding formulation: unknown velocity component '" + name +
                                         "' in 'independent' (names are body.x, body.y, body.angle (planar) or "
                                         "body.x, body.y, body.z, body.wx, body.wy, body.wz (spatial))");
            last.push_back(static_cast<int>(it - names_.begin()));
        }
        part_ = selector_.select(cv_.J, 1e-3, options_.partition.rank_tolerance, last);
        if (!same_set(part_.independent, last))
            throw InputError("", "embedding formulation: the requested independent coordinates (" +
                                     std::to_string(last.size()) + ") are not a valid independent set here; a valid one is " +
                                     independent_names());
    } else {
        part_ = selector_.select(cv_.J, initial ? options_.partition.pivot_threshold : 1.0, options_.partition.rank_tolerance);
    }
    selected_ = true;
    if (initial && log_choices_) {
        log_partition(state.t, "");
        if (!part_.redundant.empty())
            options_.log("embedding: " + redundant_rows_message(part_, [&](int r) { return system_->describe_row(r); }));
    }
}

void Partitioned::velocities(const Eigen::VectorXd& vi, Eigen::VectorXd& v) {
    // J_d v_d = -(J_i v_i + C_t) (book Eq. 6.168; Eq. 6.169), velocity_transform.hpp
    dependent_velocities(J_, cv_.C_t, part_, vi, v, transform_);
}

double Partitioned::jd_pivot_ratio(const CoordinatePartition& p) { return dependent_pivot_ratio(J_, p, transform_); }

void Partitioned::solve_accelerations(double t, const CoordinatePartition& p, const State& state,
                                      Eigen::VectorXd& vdot) {
    const int k = static_cast<int>(p.independent.size());
    system_->generalized_forces(state, Q_);
    if (!Q_.allFinite()) throw NonFiniteMotion(t, "non-finite generalized forces: the motion diverged");
    // B (Eqs. 6.80-6.85) and gamma' (Eqs. 6.90-6.94), velocity_transform.hpp
    if (!velocity_transform(J_, cv_.gamma, p, B_, gamma_prime_, transform_))
        throw DynamicsError(t, "embedding: the dependent sub-Jacobian J_d is singular (independent coordinates " +
                                   independent_names() + ")");
    // B^T M B vdot_i = B^T (Q - M gamma') (book Eq. 6.95), Cholesky (Eq. 6.99)
    MB_.noalias() = *M_ * B_;
    Mbar_.noalias() = B_.transpose() * MB_;
    Mg_.noalias() = *M_ * gamma_prime_;
    Mg_ = Q_ - Mg_;
    Qbar_.noalias() = B_.transpose() * Mg_;
    if (k > 0) {
        llt_.compute(Mbar_);
        if (llt_.info() != Eigen::Success)
            throw DynamicsError(t, "embedding: B^T M B is not positive definite");
        vdot_i_ = llt_.solve(Qbar_);
    } else {
        vdot_i_.resize(0);
    }
    vdot.noalias() = B_ * vdot_i_;
    vdot += gamma_prime_;
    if (!vdot.allFinite()) throw NonFiniteMotion(t, "non-finite accelerations: the motion diverged");
}

void Partitioned::to_ode(const State& state, Eigen::VectorXd& y) {
    if (!selected_) select(state, true);
    y.resize(ode_size());
    y.head(nq_) = state.q;
    for (size_t c = 0; c < part_.independent.size(); ++c) y[nq_ + c] = state.v[part_.independent[c]];
}

void Partitioned::from_ode(double t, const Eigen::VectorXd& y, State& state) {
    state.t = t;
    state.q = y.head(nq_);
    state.v.setZero(nv_);
    evaluate(state);
    vi_ = y.tail(ode_size() - nq_);
    velocities(vi_, state.v);
}

void Partitioned::rhs(double t, const Eigen::VectorXd& y, Eigen::VectorXd& ydot) {
    if (!y.allFinite()) throw NonFiniteMotion(t, "non-finite state: the motion diverged (try a smaller tolerance or step)");
    last_rhs_t_ = t;
    state_.t = t;
    state_.q = y.head(nq_);
    state_.v.setZero(nv_);
    evaluate(state_);  // J and C_t do not depend on v
    vi_ = y.tail(ode_size() - nq_);
    velocities(vi_, state_.v);
    evaluate(state_);  // gamma does
    solve_accelerations(t, part_, state_, vdot_);
    ydot.resize(y.size());
    write_coordinate_rates(system_->dimension(), state_.q, state_.v, ydot.head(nq_));
    for (size_t c = 0; c < part_.independent.size(); ++c) ydot[nq_ + c] = vdot_[part_.independent[c]];
}

bool Partitioned::project(double t, Eigen::VectorXd& y) {
    System& sys = *system_;
    state_.t = t;
    state_.q = y.head(nq_);
    state_.v.setZero(nv_);
    sys.normalize(state_.q);
    const CoordinatePartition& p = part_;
    // dependent positions by Newton-Raphson holding the independent directions:
    // J_d dd = -C (kept rows), q <- q (+) P_d dd (book Sec. 6.12 step 3; Ch. 3 Eq. 3.117)
    const double tol = options_.newton.tolerance * std::max(1.0, state_.q.lpNorm<Eigen::Infinity>());
    const bool converged =
        correct_dependent_positions(sys, state_, p, tol, options_.newton.iterations, cv_, J_, transform_);  // velocity_transform.hpp
    if (!converged) return false;
    // re-selection near a singular configuration (book Sec. 6.12), only at the end of an
    // accepted step (see partitioned.hpp)
    if (t >= last_rhs_t_ && p.rank > 0) {
        const double ratio = jd_pivot_ratio(p);
        if (ratio < options_.partition.reselect_ratio) {
            Eigen::VectorXd& v = v_before_;
            vi_ = y.tail(ode_size() - nq_);
            velocities(vi_, v);
            CoordinatePartition& fresh = fresh_;
            selector_.select(cv_.J, 1.0, options_.partition.rank_tolerance, {}, fresh);
            if (fresh.rank != p.rank)
                throw DynamicsError(t, "embedding: singular configuration, the constraint Jacobian has rank " +
                                           std::to_string(fresh.rank) + " instead of " + std::to_string(p.rank));
            if (!same_set(fresh.dependent, p.dependent) && jd_pivot_ratio(fresh) > ratio) {
                part_ = fresh;
                ++reselections_;
                redefined_ = true;
                if (log_choices_) {
                    char detail[80];
                    std::snprintf(detail, sizeof detail, " (pivot ratio of J_d was %.3g)", ratio);
                    options_.log("embedding: t = " + format_time(t) + ": independent coordinates now " +
                                 independent_names() + detail);
                }
                for (size_t c = 0; c < part_.independent.size(); ++c) y[nq_ + c] = v[part_.independent[c]];
            }
        }
    }
    y.head(nq_) = state_.q;
    return true;
}

void Partitioned::accelerations(const State& state, Eigen::VectorXd& vdot) {
    evaluate(state);
    CoordinatePartition p = part_;
    if (jd_pivot_ratio(p) < options_.partition.reselect_ratio) p = selector_.select(cv_.J, 1.0, options_.partition.rank_tolerance);
    solve_accelerations(state.t, p, state, vdot);
}

void Partitioned::multipliers(const State& state, Eigen::VectorXd& lambda) {
    evaluate(state);
    CoordinatePartition p = part_;
    if (jd_pivot_ratio(p) < options_.partition.reselect_ratio) p = selector_.select(cv_.J, 1.0, options_.partition.rank_tolerance);
    Eigen::VectorXd vdot;
    solve_accelerations(state.t, p, state, vdot);
    // J^T lambda = Q - M vdot (Q_c = -J^T lambda, book Eq. 6.128); its dependent rows
    // J_d^T lambda_r = (Q - M vdot)_d determine lambda; redundant rows get zero
    const Eigen::VectorXd r = Q_ - *M_ * vdot;
    multipliers_from_dependent_rows(J_, p, r, lambda, transform_);
}

}  // namespace mbd::embedding
