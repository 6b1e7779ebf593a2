// The driver of the embedded Runge-Kutta pairs (embedded_runge_kutta.hpp).
#include "embedded_runge_kutta.hpp"

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

bool EmbeddedRungeKutta::emit_inside_step(OdeProblem& problem, double t, double h, double t_new, double eps,
                                          const std::vector<double>& output_times, size_t& next,
                                          const OutputCallback& output, Eigen::VectorXd& y, IntegratorStats& stats) {
    bool have_dense = false;
    while (next < output_times.size() && output_times[next] < t_new - eps) {
        if (!have_dense) {
            dense_coefficients(problem, t, h, y, stats);
            have_dense = true;
        }
        dense_at((output_times[next] - t) / h, yout_);
        project_or_throw(problem, output_times[next], yout_);
        if (output && !output(output_times[next], yout_)) {
            y = yout_;
            return false;
        }
        ++next;
    }
    return true;
}

void EmbeddedRungeKutta::accept(OdeProblem& problem, double t_new, Eigen::VectorXd& y, const BlowUpGuard& guard,
                                IntegratorStats& stats) {
    y.swap(y1_);
    f0_.swap(f1_);  // FSAL
    guard.check(t_new, y);
    unprojected_ = y;
    project_or_throw(problem, t_new, y);
    stop_if_interrupted(t_new);  // a step boundary: SIGINT/SIGTERM/SIGHUP stop here
    // a re-selection (Formulation::state_redefined) always restarts it too
    const bool redefined = problem.state_redefined();
    if (redefined || y != unprojected_) {
        problem.rhs(t_new, y, f0_);  // restart the FSAL derivative at the projected state
        ++stats.rhs_evaluations;
    }
}

void EmbeddedRungeKutta::integrate(OdeProblem& problem, double t0, Eigen::VectorXd& y,
                                   const std::vector<double>& output_times, const OutputCallback& output,
                                   IntegratorStats& stats) {
    size_t next = open_adaptive_run(name(), settings_, problem, t0, y, output_times, output);
    if (next == output_times.size()) return;
    for (Eigen::VectorXd* v : {&f0_, &f1_, &y1_, &unprojected_, &yout_}) v->resize(problem.size());
    prepare(problem.size());

    const double t_end = output_times.back();
    const double eps = time_epsilon(t0, t_end);
    const double span = t_end - t0;
    if (!(settings_.max_step >= 0.0) || !std::isfinite(settings_.max_step))
        throw InputError(name(), "needs a non-negative max_step (0: no limit), got " + format_time(settings_.max_step));
    const double hmax = settings_.max_step > 0.0 ? std::min(settings_.max_step, std::max(span, eps)) : std::max(span, eps);
    BlowUpGuard guard;
    guard.reset(y);

    double t = t0;
    events_.start(problem, t0, y);
    problem.rhs(t, y, f0_);
    ++stats.rhs_evaluations;
    double h = settings_.step > 0.0 ? std::min(settings_.step, hmax) : initial_step(problem, t, y, hmax, stats);

    const double safe = control_.safety, beta = control_.beta, expo1 = control_.alpha;
    const double facc1 = 1.0 / control_.min_ratio, facc2 = 1.0 / control_.max_ratio;
    double facold = 1e-4;
    bool reject = false;
    long attempts = 0;

    while (next < output_times.size()) {
        check_progress(t, h, span, ++attempts);
        // do not step past the end time
        bool last = false;
        if (t + h >= t_end - eps) {
            h = t_end - t;
            last = true;
        }
        const double t_new = last ? t_end : t + h;
        double err = attempt(problem, t, h, t_new, y, stats);
        if (!std::isfinite(err)) err = 1e10;
        const double fac11 = std::pow(std::max(err, 1e-300), expo1);
        if (err > 1.0) {
            ++stats.rejected_steps;
            h = h / std::min(facc1, fac11 / safe);
            reject = true;
            continue;
        }
        end_derivative(problem, t_new, stats);
        double fac = fac11 / std::pow(facold, beta);
        fac = std::max(facc2, std::min(facc1, fac / safe));
        double h_new = h / fac;
        facold = std::max(err, 1e-4);
        if (reject) h_new = std::min(h_new, h);
        double t_step = t_new, h_step = h;  // the step taken: shortened to end on an event
        const bool at_event = events_.active() && events_.left_side(problem, t_new, y1_);
        if (at_event) {
            dense_coefficients(problem, t, h, y, stats);
            const double theta =
                events_.locate(problem, t, h, [&](double th, Eigen::VectorXd& out) { dense_at(th, out); });
            h_step = theta * h;
            t_step = t + h_step;
            attempt(problem, t, h_step, t_step, y, stats);  // shorter than the accepted step: within tolerance
            end_derivative(problem, t_step, stats);
        }
        ++stats.steps;
        if (!emit_inside_step(problem, t, h_step, t_step, eps, output_times, next, output, y, stats)) return;
        accept(problem, t_step, y, guard, stats);
        t = t_step;
        if (at_event && events_.handle(problem, t, y, stats)) {
            problem.rhs(t, y, f0_);  // the impact changed y: restart the FSAL derivative there
            ++stats.rhs_evaluations;
        }
        if (!emit_outputs_up_to(t + eps, y, output_times, next, output)) return;
        reject = false;
        h = std::min(h_new, hmax);
    }
}

}  // namespace mbd::integrators
