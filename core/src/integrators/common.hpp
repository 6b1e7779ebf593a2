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
std::unique_ptr<Integrator> make_dop853(const IntegratorSettings& settings);
std::unique_ptr<Integrator> make_generalized_alpha(const IntegratorSettings& settings);
std::unique_ptr<Integrator> make_cvode(const IntegratorSettings& settings);

// Output times must not decrease and must not lie before t0.
void check_output_times(const std::string& integrator, double t0, const std::vector<double>& output_times);

// Input checks before a run; each throws InputError naming the integrator.
void require_fixed_step(const std::string& integrator, const IntegratorSettings& settings);
void require_state_size(const std::string& integrator, const OdeProblem& problem, const Eigen::VectorXd& y);

// The opening of an adaptive run (dopri5, dop853, cvode): checks the output times, the
// tolerance and the state size, then reports the outputs at the start time. Returns
// the index of the first output time still to integrate to; output_times.size() when
// nothing is left (no output times, all at t0, or the callback stopped the run).
size_t open_adaptive_run(const std::string& integrator, const IntegratorSettings& settings, const OdeProblem& problem,
                         double t0, const Eigen::VectorXd& y, const std::vector<double>& output_times,
                         const OutputCallback& output);

// Reports y at the output times from `next` on that are <= limit, advancing `next`;
// false when the callback stopped the run.
bool emit_outputs_up_to(double limit, const Eigen::VectorXd& y, const std::vector<double>& output_times, size_t& next,
                        const OutputCallback& output);

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

// The time grid of the fixed-step integrators (euler, rk4, generalized_alpha): steps
// of settings.step from t0 through every output time, the last step before each
// output shortened to end exactly on it (a remainder shorter than 1e-6 h is merged
// into the previous step). `advance(t, t_next)` takes one step and counts it in
// stats.steps; `emit(t, t_out)` reports the output at t_out and returns false to stop.
template <class AdvanceFn, class EmitFn>
void march_fixed_steps(const std::string& integrator, const IntegratorSettings& settings, double t0,
                       const std::vector<double>& output_times, const IntegratorStats& stats, AdvanceFn&& advance,
                       EmitFn&& emit) {
    const double h = settings.step;
    double t = t0;
    const double eps = output_times.empty() ? 0.0 : time_epsilon(t0, output_times.back());
    for (double t_out : output_times) {
        const double span = t_out - t;
        if (span > eps) {
            long n = static_cast<long>(std::ceil(span / h - 1e-6));
            if (n < 1) n = 1;
            const double t_start = t;
            for (long k = 1; k <= n; ++k) {
                const double t_next = (k == n) ? t_out : t_start + static_cast<double>(k) * h;
                if (stats.steps >= settings.max_steps)
                    throw DynamicsError(t, integrator + ": the maximum number of steps (" +
                                               std::to_string(settings.max_steps) + ") was reached at t = " +
                                               format_time(t));
                advance(t, t_next);
                t = t_next;
                stop_if_interrupted(t);  // a step boundary: SIGINT/SIGTERM/SIGHUP stop here
            }
        }
        t = std::max(t, t_out);
        if (!emit(t, t_out)) return;
    }
}

// An adaptive integrator (dopri5, dop853, cvode): it chooses its own steps for
// settings.tolerance; its run opens with open_adaptive_run.
class AdaptiveIntegrator : public Integrator {
public:
    explicit AdaptiveIntegrator(const IntegratorSettings& settings) : settings_(settings) {}
    bool adaptive() const final { return true; }

protected:
    IntegratorSettings settings_;
};

// An explicit one-step method with a fixed step (euler, rk4): the run checks its
// inputs, then steps of settings.step through the output times, guarding against
// blow-up and projecting after each step. A method supplies only its step.
class FixedStepIntegrator : public Integrator {
public:
    explicit FixedStepIntegrator(const IntegratorSettings& settings) : settings_(settings) {}
    bool adaptive() const final { return false; }
    void integrate(OdeProblem& problem, double t0, Eigen::VectorXd& y, const std::vector<double>& output_times,
                   const OutputCallback& output, IntegratorStats& stats) final;

protected:
    // Sizes the work vectors for n unknowns (before the run: none are allocated during it).
    virtual void prepare(int n) = 0;
    // Advances y in place from t to t + h, counting its right-hand-side evaluations.
    virtual void step(OdeProblem& problem, double t, double h, Eigen::VectorXd& y, IntegratorStats& stats) = 0;

private:
    IntegratorSettings settings_;
};

}  // namespace mbd::integrators
