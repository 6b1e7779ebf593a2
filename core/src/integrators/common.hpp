// Shared pieces of the integrators (core/src/integrators/): output
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

// Output times must not decrease and must not lie before t0.
void check_output_times(const std::string& integrator, double t0, const std::vector<double>& output_times);

// Input checks before a run; each throws InputError naming the integrator.
void require_fixed_step(const std::string& integrator, const IntegratorSettings& settings);
void require_state_size(const std::string& integrator, const OdeProblem& problem, const Eigen::VectorXd& y);

// The checks at the start of an adaptive run (dopri5, dop853, cvode): the tolerance and
// the state size; each throws InputError naming the integrator.
void require_adaptive_start(const std::string& integrator, const IntegratorSettings& settings,
                            const OdeProblem& problem, const Eigen::VectorXd& y);

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

// The time grid of the fixed-step integrators (euler, rk4, generalized_alpha): steps of h
// from the time a stretch toward a stop time starts, t_k = start + k h, the last step before
// the stop shortened to end exactly on it (a remainder shorter than 1e-6 h is merged into
// the previous step). A new stop time starts a new stretch; an infinite one has no end.
class FixedStepGrid {
public:
    void start(double t0) {
        start_ = t0;
        stop_ = std::nan("");
        taken_ = 0;
    }
    // The end of the next step from t toward t_stop (> t).
    double next(double t, double t_stop, double h) {
        if (!(t_stop == stop_)) {
            start_ = t;
            stop_ = t_stop;
            taken_ = 0;
        }
        if (std::isinf(t_stop)) return start_ + static_cast<double>(taken_ + 1) * h;
        long n = static_cast<long>(std::ceil((t_stop - start_) / h - 1e-6));
        if (n < 1) n = 1;
        return taken_ + 1 >= n ? t_stop : start_ + static_cast<double>(taken_ + 1) * h;
    }
    // The step to next() was taken.
    void taken() { ++taken_; }

private:
    double start_ = 0.0, stop_ = 0.0;
    long taken_ = 0;
};

// Stops a fixed-step run that has taken settings.max_steps steps.
void check_step_count(const std::string& integrator, const IntegratorSettings& settings, const IntegratorStats& stats,
                      double t);

// An adaptive integrator (dopri5, dop853, cvode): it chooses its own steps for
// settings.tolerance; its run opens with open_adaptive_run.
class AdaptiveIntegrator : public Integrator {
public:
    explicit AdaptiveIntegrator(const IntegratorSettings& settings) : settings_(settings) {}

protected:
    IntegratorSettings settings_;
};

// An explicit one-step method with a fixed step (euler, rk4): the run checks its
// inputs, then steps of settings.step on the FixedStepGrid, guarding against blow-up and
// projecting after each step. A method supplies only its step.
class FixedStepIntegrator : public Integrator {
public:
    explicit FixedStepIntegrator(const IntegratorSettings& settings) : settings_(settings) {}
    void begin(OdeProblem& problem, double t0, const Eigen::VectorXd& y0, double t_end,
               IntegratorStats& stats) final;
    bool step(double t_stop, StepOutputs* outputs) final;
    double time() const final { return t_; }
    const Eigen::VectorXd& state() const final { return y_; }

protected:
    // Sizes the work vectors for n unknowns (before the run: none are allocated during it).
    virtual void prepare(int n) = 0;
    // Advances y in place from t to t + h, counting its right-hand-side evaluations.
    virtual void step(OdeProblem& problem, double t, double h, Eigen::VectorXd& y, IntegratorStats& stats) = 0;

private:
    IntegratorSettings settings_;
    OdeProblem* problem_ = nullptr;
    IntegratorStats* stats_ = nullptr;
    double t_ = 0.0;
    Eigen::VectorXd y_;
    FixedStepGrid grid_;
    BlowUpGuard guard_;
};

}  // namespace mbd::integrators
