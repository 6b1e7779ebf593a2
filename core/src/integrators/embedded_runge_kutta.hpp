// The driver shared by the embedded explicit Runge-Kutta pairs (dopri5, dop853), after
// Hairer, Norsett & Wanner, "Solving Ordinary Differential Equations I", 2nd ed.,
// Sec. II.4 (step-size control, HINIT) and II.6 (dense output), as in their codes
// DOPRI5 and DOP853: Hairer's PI step-size controller, accept/reject, the first step,
// output from the continuous extension, event location on it (event_locator.hpp),
// projection after every accepted step, and the checks (step collapse, step count,
// blow-up). A pair supplies its stages, its error norm and its continuous extension.
//
// The derivative at the start of a step is f0_, the one at its end f1_ (FSAL: it becomes
// the next step's f0_); the solution at the end is y1_.
#pragma once

#include "common.hpp"
#include "event_locator.hpp"

#include <string>
#include <utility>

namespace mbd::integrators {

// Hairer's PI controller: h_new = h / fac with fac = err^alpha / err_old^beta / safety,
// the ratio h_new / h limited to [min_ratio, max_ratio] (no increase right after a
// rejection). HINIT's first step uses the error's order in h.
struct StepControl {
    double alpha;      // 1/q - (a multiple of) beta, q the order of err in h
    double beta;       // Lund stabilisation; 0 is the classical (I) controller
    double safety;
    double min_ratio, max_ratio;
    int error_order;   // q: err ~ h^q (HINIT: h ~ (0.01 / |f'|)^(1/q))
};

class EmbeddedRungeKutta : public AdaptiveIntegrator {
public:
    // control: the step-control defaults of Hairer's code of the same name (dopri5, dop853).
    EmbeddedRungeKutta(const IntegratorSettings& settings, const StepControl& control)
        : AdaptiveIntegrator(settings), control_(control) {}
    bool stops_at_outputs() const final { return false; }
    void begin(OdeProblem& problem, double t0, const Eigen::VectorXd& y0, double t_end,
               IntegratorStats& stats) final;
    bool step(double t_stop, StepOutputs* outputs) final;
    void rhs_changed() final;
    double time() const final { return t_; }
    const Eigen::VectorXd& state() const final { return y_; }

    // For a caller that asks for times inside the steps (the Simulator's advance_to): the
    // state at t from the continuous extension of the last accepted step, projected, when
    // that step had it computed (an output time inside it, StepOutputs) and t lies in it;
    // false otherwise.
    bool interpolate(double t, Eigen::VectorXd& y);
    // Continue from (t, y) instead, with the step size and controller as they are (the
    // right-hand side changed at a time the run had stepped past): FSAL derivative at (t, y).
    void rewind(double t, const Eigen::VectorXd& y);

protected:
    // Sizes the pair's own work vectors for n unknowns (none are allocated during the run).
    virtual void prepare(int n) = 0;
    // The stages of a step of size h from (t, y) ending at t_new, with f0_ = f(t, y): the
    // solution in y1_. Returns the norm of the embedded error estimate (accepted when <= 1;
    // the driver takes a non-finite one as 1e10, a rejection).
    virtual double attempt(OdeProblem& problem, double t, double h, double t_new, const Eigen::VectorXd& y,
                           IntegratorStats& stats) = 0;
    // After the error test passed: f1_ = f(t_new, y1_), unless attempt has it already.
    virtual void end_derivative(OdeProblem& /*problem*/, double /*t_new*/, IntegratorStats& /*stats*/) {}
    // The continuous extension of the step of size h from (t, y) just attempted (after
    // end_derivative), and its value at the step fraction theta in [0, 1].
    virtual void dense_coefficients(OdeProblem& problem, double t, double h, const Eigen::VectorXd& y,
                                    IntegratorStats& stats) = 0;
    virtual void dense_at(double theta, Eigen::VectorXd& out) const = 0;

    // The weighted RMS norm of the integrators: sqrt(1/n sum (e_i / sk_i)^2) with
    // sk_i = tol + tol max(|y0_i|, |y1_i|) (rtol = atol = settings.tolerance).
    double scale(const Eigen::VectorXd& y0, const Eigen::VectorXd& y1, Eigen::Index i) const {
        const double tol = settings_.tolerance;
        return tol + tol * std::max(std::abs(y0[i]), std::abs(y1[i]));
    }

    Eigen::VectorXd f0_, f1_, y1_;

private:
    double initial_step(OdeProblem& problem, double t, const Eigen::VectorXd& y, double hmax, IntegratorStats& stats);
    // Stops the run when the step has collapsed or the attempts exceed settings.max_steps.
    void check_progress(double t, double h, double span, long attempts) const;
    // Output at the output times inside (t, t_new) from the continuous extension of
    // the accepted step; false when the callback stopped the run (y is then that output).
    bool emit_inside_step(double h, double t_new, StepOutputs& outputs);
    // Takes the accepted step: y_ <- y1_, FSAL, blow-up guard, projection.
    void accept(double t_new);

    StepControl control_;
    // the run between step() calls: the problem, the time and state, the next step's size and
    // the controller's memory (Hairer's facold, a rejection just before)
    OdeProblem* problem_ = nullptr;
    IntegratorStats* stats_ = nullptr;
    double t_ = 0.0, h_ = 0.0, hmax_ = 0.0, eps_ = 0.0, span_ = 0.0, facold_ = 1e-4;
    bool reject_ = false;
    long attempts_ = 0;
    Eigen::VectorXd y_;
    BlowUpGuard guard_;
    Eigen::VectorXd unprojected_, yout_;
    EventLocator events_;
    double dense_from_ = 0.0, dense_h_ = 0.0;  // the step whose continuous extension is at hand (0: none)
};

}  // namespace mbd::integrators
