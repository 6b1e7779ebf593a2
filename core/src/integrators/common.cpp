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

size_t open_adaptive_run(const std::string& integrator, const IntegratorSettings& settings, const OdeProblem& problem,
                         double t0, const Eigen::VectorXd& y, const std::vector<double>& output_times,
                         const OutputCallback& output) {
    check_output_times(integrator, t0, output_times);
    if (!(settings.tolerance > 0.0)) throw InputError(integrator, "needs a positive tolerance");
    require_state_size(integrator, problem, y);
    if (output_times.empty()) return 0;
    const double eps = time_epsilon(t0, output_times.back());
    size_t next = 0;
    if (!emit_outputs_up_to(t0 + eps, y, output_times, next, output)) return output_times.size();
    return next;
}

bool emit_outputs_up_to(double limit, const Eigen::VectorXd& y, const std::vector<double>& output_times, size_t& next,
                        const OutputCallback& output) {
    while (next < output_times.size() && output_times[next] <= limit) {
        if (output && !output(output_times[next], y)) return false;
        ++next;
    }
    return true;
}

void FixedStepIntegrator::integrate(OdeProblem& problem, double t0, Eigen::VectorXd& y,
                                    const std::vector<double>& output_times, const OutputCallback& output,
                                    IntegratorStats& stats) {
    prepare(problem.size());
    require_fixed_step(name(), settings_);
    check_output_times(name(), t0, output_times);
    require_state_size(name(), problem, y);
    BlowUpGuard guard;
    guard.reset(y);
    march_fixed_steps(
        name(), settings_, t0, output_times, stats,
        [&](double t, double t_next) {
            step(problem, t, t_next - t, y, stats);
            ++stats.steps;
            guard.check(t_next, y);
            project_or_throw(problem, t_next, y);
        },
        [&](double, double t_out) { return !output || output(t_out, y); });
}

}  // namespace mbd::integrators
