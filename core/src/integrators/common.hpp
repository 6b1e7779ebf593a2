// Shared pieces of the integrators (core/src/integrators/): factories, output
// bookkeeping, and the checks every integrator applies to its state.
#pragma once

#include <mbd/integrator.hpp>
#include <mbd/interrupt.hpp>
#include <mbd/sdk/params.hpp>
#include <mbd/sdk/text.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace mbd::integrators {

std::unique_ptr<Integrator> make_euler(const IntegratorSettings& settings);
std::unique_ptr<Integrator> make_rk4(const IntegratorSettings& settings);
std::unique_ptr<Integrator> make_dopri5(const IntegratorSettings& settings);
std::unique_ptr<Integrator> make_generalized_alpha(const IntegratorSettings& settings);
std::unique_ptr<Integrator> make_cvode(const IntegratorSettings& settings);

// Output times must not decrease and must not lie before t0.
void check_output_times(const std::string& integrator, double t0, const std::vector<double>& output_times);

// Two times closer than this (relative to the run's time scale) are the same time.
inline double time_epsilon(double t0, double t_end) {
    return 64.0 * 2.220446049250313e-16 * std::max({1.0, std::abs(t0), std::abs(t_end)});
}

// Watches a state for NaN/Inf and for growth far beyond its initial size
// (an explicit method on a problem too stiff for its step). Throws DynamicsError.
class BlowUpGuard {
public:
    void reset(const Eigen::VectorXd& y0) { limit_ = kGrowth * (1.0 + y0.lpNorm<Eigen::Infinity>()); }
    void check(double t, const Eigen::VectorXd& y) const;

private:
    static constexpr double kGrowth = 1e12;
    double limit_ = 0.0;
};

// Project a state; throw DynamicsError if the formulation reports failure.
void project_or_throw(OdeProblem& problem, double t, Eigen::VectorXd& y);

// The fixed-step driver shared by euler and rk4: steps of settings.step,
// shortening the last step before each output time, project() after each step.
// `step(t, h, y)` advances y in place from t to t + h.
template <class StepFn>
void fixed_step_run(const std::string& name, const IntegratorSettings& settings, OdeProblem& problem, double t0,
                    Eigen::VectorXd& y, const std::vector<double>& output_times, const OutputCallback& output,
                    IntegratorStats& stats, StepFn&& step) {
    if (!(settings.step > 0.0) || !std::isfinite(settings.step))
        throw InputError(name, "needs a positive fixed step (settings.step), got " + format_time(settings.step));
    check_output_times(name, t0, output_times);
    if (y.size() != problem.size())
        throw InputError(name, "state size " + std::to_string(y.size()) + " does not match the problem size " +
                                   std::to_string(problem.size()));
    BlowUpGuard guard;
    guard.reset(y);
    const double h = settings.step;
    double t = t0;
    const double eps = output_times.empty() ? 0.0 : time_epsilon(t0, output_times.back());
    for (double t_out : output_times) {
        // Steps of h from t; the last one ends exactly at t_out. A remainder
        // shorter than 1e-6 h is merged into the previous step.
        const double span = t_out - t;
        if (span > eps) {
            long n = static_cast<long>(std::ceil(span / h - 1e-6));
            if (n < 1) n = 1;
            const double t_start = t;
            for (long k = 1; k <= n; ++k) {
                const double t_next = (k == n) ? t_out : t_start + static_cast<double>(k) * h;
                if (stats.steps >= settings.max_steps)
                    throw DynamicsError(t, name + ": the maximum number of steps (" +
                                               std::to_string(settings.max_steps) + ") was reached at t = " +
                                               format_time(t));
                step(t, t_next - t, y);
                ++stats.steps;
                t = t_next;
                guard.check(t, y);
                project_or_throw(problem, t, y);
                stop_if_interrupted(t);  // a step boundary: SIGINT/SIGTERM/SIGHUP stop here
            }
        }
        t = std::max(t, t_out);
        if (output && !output(t_out, y)) return;
    }
}

}  // namespace mbd::integrators
