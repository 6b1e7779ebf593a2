// The driver of the embedded Runge-Kutta pairs (embedded_runge_kutta.hpp).
#include "embedded_runge_kutta.hpp"
#include <mbd/kit/non_finite_motion.hpp>

#include <cmath>

namespace mbd::integrators {

double EmbeddedRungeKutta::initial_step(OdeProblem& problem, double t, const Eigen::VectorXd& y, double hmax,
                                        IntegratorStats& stats) {
    // Hairer's HINIT: an explicit Euler step of guessed size, then h ~ (0.01 / max(|f|, |f'|))^(1/q).
    // y1_ and f1_ are free before the first step: they hold the Euler step and its derivative.
    const double tol = settings_.tolerance;
    const double n = std::max<double>(1.0, static_cast<double>(y.size()));
    double dnf = 0.0, dny = 0.0;
    for (Eigen::Index i = 0; i < y.size(); ++i) {
        const double sk = tol + tol * std::abs(y[i]);
        dnf += (f0_[i] / sk) * (f0_[i] / sk);
        dny += (y[i] / sk) * (y[i] / sk);
    }
    dnf /= n;
    dny /= n;
    double h = (dnf <= 1e-10 || dny <= 1e-10) ? 1e-6 : std::sqrt(dny / dnf) * 0.01;
    h = std::min(h, hmax);
    y1_ = y + h * f0_;
    problem.rhs(t + h, y1_, f1_);
    ++stats.rhs_evaluations;
    double der2 = 0.0;
    for (Eigen::Index i = 0; i < y.size(); ++i) {
        const double sk = tol + tol * std::abs(y[i]);
        const double d = (f1_[i] - f0_[i]) / sk;
        der2 += d * d;
    }
    der2 = std::sqrt(der2 / n) / h;
    const double der12 = std::max(std::abs(der2), std::sqrt(dnf));
    const double h1 =
        der12 <= 1e-15 ? std::max(1e-6, h * 1e-3) : std::pow(0.01 / der12, 1.0 / control_.error_order);
    if (!std::isfinite(h1)) return std::min(h, hmax);
    return std::min({100.0 * h, h1, hmax});
}

void EmbeddedRungeKutta::check_progress(double t, double h, double span, long attempts) const {
    const double scale = std::max(std::abs(t), span);
    if (h < settings_.min_step * scale)
        throw DynamicsError(t, "step size collapse at t = " + format_time(t) + " (h = " + format_time(h) +
                                   "): the problem is too stiff for an explicit integrator or the motion is "
                                   "singular; try --integrator generalized_alpha or cvode");
    if (attempts > settings_.max_steps)
        throw DynamicsError(t, name() + ": the maximum number of steps (" + std::to_string(settings_.max_steps) +
                                   ") was exceeded at t = " + format_time(t) +
                                   "; the problem may be stiff (try --integrator cvode or generalized_alpha)");
}

bool EmbeddedRungeKutta::emit_inside_step(double h, double t_new, StepOutputs& outputs) {
    bool have_dense = false;
    const std::vector<double>& times = outputs.times;
    while (outputs.next < times.size() && times[outputs.next] < t_new - eps_) {
        if (!have_dense) {
            dense_coefficients(*problem_, t_, h, y_, *stats_);
            have_dense = true;
            dense_from_ = t_;
            dense_h_ = h;
        }
        if (!outputs.output) {  // only the extension wanted (interpolate): no output to make
            ++outputs.next;
            continue;
        }
        dense_at((times[outputs.next] - t_) / h, yout_);
        project_or_throw(*problem_, times[outputs.next], yout_);
        if (!outputs.output(times[outputs.next], yout_)) {
            outputs.stopped = yout_;
            return false;
        }
        ++outputs.next;
    }
    return true;
}

void EmbeddedRungeKutta::accept(double t_new) {
    y_.swap(y1_);
    f0_.swap(f1_);  // FSAL
    guard_.check(t_new, y_);
    unprojected_ = y_;
    project_or_throw(*problem_, t_new, y_);
    stop_if_interrupted(t_new);  // a step boundary: SIGINT/SIGTERM/SIGHUP stop here
    // a re-selection (Formulation::state_redefined) always restarts it too
    const bool redefined = problem_->state_redefined();
    if (redefined || y_ != unprojected_) {
        problem_->rhs(t_new, y_, f0_);  // restart the FSAL derivative at the projected state
        ++stats_->rhs_evaluations;
    }
}

void EmbeddedRungeKutta::begin(OdeProblem& problem, double t0, const Eigen::VectorXd& y0, double t_end,
                               IntegratorStats& stats) {
    require_adaptive_start(name(), settings_, problem, y0);
    if (!(settings_.max_step >= 0.0) || !std::isfinite(settings_.max_step))
        throw InputError(name(), "needs a non-negative max_step (0: no limit), got " + format_time(settings_.max_step));
    problem_ = &problem;
    stats_ = &stats;
    for (Eigen::VectorXd* v : {&f0_, &f1_, &y1_, &unprojected_, &yout_}) v->resize(problem.size());
    prepare(problem.size());
    eps_ = time_epsilon(t0, t_end);
    span_ = t_end - t0;
    hmax_ = settings_.max_step > 0.0 ? std::min(settings_.max_step, std::max(span_, eps_)) : std::max(span_, eps_);
    y_ = y0;
    guard_.reset(y_);
    t_ = t0;
    dense_h_ = 0.0;
    events_.start(problem, t0, y_);
    problem.rhs(t_, y_, f0_);
    ++stats.rhs_evaluations;
    h_ = settings_.step > 0.0 ? std::min(settings_.step, hmax_) : initial_step(problem, t_, y_, hmax_, stats);
    facold_ = 1e-4;
    reject_ = false;
    attempts_ = 0;
}

void EmbeddedRungeKutta::rhs_changed() {
    if (!problem_) return;
    problem_->rhs(t_, y_, f0_);  // the FSAL stage of the old right-hand side no longer holds
    ++stats_->rhs_evaluations;
}

bool EmbeddedRungeKutta::interpolate(double t, Eigen::VectorXd& y) {
    if (!(dense_h_ > 0.0) || t < dense_from_ || t > dense_from_ + dense_h_) return false;
    dense_at((t - dense_from_) / dense_h_, y);
    project_or_throw(*problem_, t, y);
    return true;
}

void EmbeddedRungeKutta::rewind(double t, const Eigen::VectorXd& y) {
    t_ = t;
    y_ = y;
    dense_h_ = 0.0;
    problem_->rhs(t_, y_, f0_);
    ++stats_->rhs_evaluations;
}

bool EmbeddedRungeKutta::step(double t_stop, StepOutputs* outputs) {
    if (!problem_) throw InputError(name(), "step() before begin()");
    OdeProblem& problem = *problem_;
    dense_h_ = 0.0;  // the stages are about to change
    const double safe = control_.safety, beta = control_.beta, expo1 = control_.alpha;
    const double facc1 = 1.0 / control_.min_ratio, facc2 = 1.0 / control_.max_ratio;
    double h = h_;
    for (;;) {
        check_progress(t_, h, span_, ++attempts_);
        // do not step past the stop time; a step cut short there leaves the next one its size
        bool last = false;
        const double h_wanted = h;
        if (t_ + h >= t_stop - eps_) {
            h = t_stop - t_;
            last = true;
        }
        const double t_new = last ? t_stop : t_ + h;
        double err;
        try {
            err = attempt(problem, t_, h, t_new, y_, *stats_);
        } catch (const NonFiniteMotion&) {  // a stage landed where the motion is not finite: too long a step
            err = 1e10;
        }
        if (!std::isfinite(err)) err = 1e10;
        const double fac11 = std::pow(std::max(err, 1e-300), expo1);
        if (err > 1.0) {
            ++stats_->rejected_steps;
            h = h / std::min(facc1, fac11 / safe);
            h_ = h;
            reject_ = true;
            continue;
        }
        end_derivative(problem, t_new, *stats_);
        double fac = fac11 / std::pow(facold_, beta);
        fac = std::max(facc2, std::min(facc1, fac / safe));
        double h_new = h / fac;
        facold_ = std::max(err, 1e-4);
        if (reject_) h_new = std::min(h_new, h);
        if (last) h_new = std::max(h_new, h_wanted);  // the controller's own proposal before the cut
        double t_step = t_new, h_step = h;  // the step taken: shortened to end on an event
        const bool at_event = events_.active() && events_.left_side(problem, t_new, y1_);
        if (at_event) {
            dense_coefficients(problem, t_, h, y_, *stats_);
            const double theta =
                events_.locate(problem, t_, h, [&](double th, Eigen::VectorXd& out) { dense_at(th, out); });
            h_step = theta * h;
            t_step = t_ + h_step;
            attempt(problem, t_, h_step, t_step, y_, *stats_);  // shorter than the accepted step: within tolerance
            end_derivative(problem, t_step, *stats_);
        }
        ++stats_->steps;
        reject_ = false;
        h_ = std::min(h_new, hmax_);
        if (outputs && !emit_inside_step(h_step, t_step, *outputs)) return false;
        accept(t_step);
        t_ = t_step;
        if (at_event && events_.handle(problem, t_, y_, *stats_)) {
            problem.rhs(t_, y_, f0_);  // the impact changed y: restart the FSAL derivative there
            ++stats_->rhs_evaluations;
        }
        return true;
    }
}

}  // namespace mbd::integrators
