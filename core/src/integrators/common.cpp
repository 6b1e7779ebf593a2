// The helpers shared by the integrators (common.hpp): input checks, the opening of
// an adaptive run, the blow-up guard, projection, and the fixed-step run.
#include "common.hpp"

namespace mbd::integrators {

void check_output_times(const std::string& integrator, double t0, const std::vector<double>& output_times) {
    double previous = t0;
    for (double t : output_times) {
        if (!std::isfinite(t) || t < previous)
            throw InputError(integrator, "output times must be finite and must not decrease from the start time " +
                                             format_time(t0) + " (got " + format_time(t) + " after " +
                                             format_time(previous) + ")");
        previous = t;
    }
}

void BlowUpGuard::check(double t, const Eigen::VectorXd& y) const {
    const bool finite = y.allFinite();
    if (!finite || y.lpNorm<Eigen::Infinity>() > limit_)
        throw DynamicsError(t, std::string("state ") + (finite ? "grew without bound" : "became non-finite") +
                                   " at t = " + format_time(t) +
                                   ": step too large for this stiff problem (use a smaller step, or "
                                   "--integrator generalized_alpha or cvode)");
}

void project_or_throw(OdeProblem& problem, double t, Eigen::VectorXd& y) {
    if (!problem.project(t, y))
        throw DynamicsError(t, "projection onto the constraint manifold failed at t = " + format_time(t));
}

void require_fixed_step(const std::string& integrator, const IntegratorSettings& settings) {
    if (!(settings.step > 0.0) || !std::isfinite(settings.step))
        throw InputError(integrator, "needs a positive fixed step (settings.step), got " + format_time(settings.step));
}

void require_state_size(const std::string& integrator, const OdeProblem& problem, const Eigen::VectorXd& y) {
    if (y.size() != problem.size())
        throw InputError(integrator, "state size " + std::to_string(y.size()) + " does not match the problem size " +
                                         std::to_string(problem.size()));
}

void require_adaptive_start(const std::string& integrator, const IntegratorSettings& settings,
                            const OdeProblem& problem, const Eigen::VectorXd& y) {
    if (!(settings.tolerance > 0.0)) throw InputError(integrator, "needs a positive tolerance");
    require_state_size(integrator, problem, y);
}

bool emit_outputs_up_to(double limit, const Eigen::VectorXd& y, const std::vector<double>& output_times, size_t& next,
                        const OutputCallback& output) {
    while (next < output_times.size() && output_times[next] <= limit) {
        if (output && !output(output_times[next], y)) return false;
        ++next;
    }
    return true;
}

void check_step_count(const std::string& integrator, const IntegratorSettings& settings, const IntegratorStats& stats,
                      double t) {
    if (stats.steps >= settings.max_steps)
        throw DynamicsError(t, integrator + ": the maximum number of steps (" + std::to_string(settings.max_steps) +
                                   ") was reached at t = " + format_time(t));
}

void FixedStepIntegrator::begin(OdeProblem& problem, double t0, const Eigen::VectorXd& y0, double /*t_end*/,
                                IntegratorStats& stats) {
    prepare(problem.size());
    require_fixed_step(name(), settings_);
    require_state_size(name(), problem, y0);
    problem_ = &problem;
    stats_ = &stats;
    t_ = t0;
    y_ = y0;
    grid_.start(t0);
    guard_.reset(y0);
}

bool FixedStepIntegrator::step(double t_stop, StepOutputs* /*outputs: the steps end on each*/) {
    if (!problem_) throw InputError(name(), "step() before begin()");
    const double t_next = grid_.next(t_, t_stop, settings_.step);
    check_step_count(name(), settings_, *stats_, t_);
    step(*problem_, t_, t_next - t_, y_, *stats_);
    ++stats_->steps;
    grid_.taken();
    guard_.check(t_next, y_);
    project_or_throw(*problem_, t_next, y_);
    t_ = t_next;
    stop_if_interrupted(t_);  // a step boundary: SIGINT/SIGTERM/SIGHUP stop here
    return true;
}

}  // namespace mbd::integrators

namespace mbd {

void Integrator::integrate(OdeProblem& problem, double t0, Eigen::VectorXd& y, const std::vector<double>& output_times,
                           const OutputCallback& output, IntegratorStats& stats) {
    integrators::check_output_times(name(), t0, output_times);
    if (output_times.empty()) return;
    const double t_end = output_times.back();
    begin(problem, t0, y, t_end, stats);
    const double eps = integrators::time_epsilon(t0, t_end);
    StepOutputs outputs{output_times, 0, output, {}};
    for (;;) {
        if (!integrators::emit_outputs_up_to(time() + eps, state(), output_times, outputs.next, output)) break;
        if (outputs.next == output_times.size()) break;
        const double t_stop = stops_at_outputs() ? output_times[outputs.next] : t_end;
        if (!step_toward(*this, problem, t_stop, &outputs)) {
            y = outputs.stopped;
            return;
        }
    }
    y = state();
}


bool step_toward(Integrator& integrator, OdeProblem& problem, double t_stop, StepOutputs* outputs) {
    const double breakpoint = problem.next_breakpoint(integrator.time());
    if (!(breakpoint <= t_stop)) return integrator.step(t_stop, outputs);
    problem.set_step_end(breakpoint);
    bool going = true;
    try {
        going = integrator.step(breakpoint, outputs);
    } catch (...) {
        problem.set_step_end(std::nan(""));
        throw;
    }
    problem.set_step_end(std::nan(""));
    if (integrator.time() == breakpoint) integrator.rhs_changed();  // the next step starts on the jump's far side
    return going;
}

}  // namespace mbd
