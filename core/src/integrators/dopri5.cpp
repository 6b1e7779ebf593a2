// Dormand-Prince 5(4) (Dormand & Prince 1980; Hairer, Norsett & Wanner,
// "Solving Ordinary Differential Equations I", 2nd ed., Sec. II.4-II.6, code DOPRI5):
// seven stages with FSAL, local extrapolation (the 5th-order solution is kept),
// the embedded 4th-order error estimate, Hairer's PI step-size controller
// (beta = 0.04) and the 4th-order continuous extension for output between steps.
// project() runs after every accepted step; if it moves y, the FSAL derivative
// is recomputed at the projected state.
// Events (OdeProblem::event_count): after an accepted step the event functions are
// checked; on a sign change the root is located on the continuous extension and the
// step re-taken to end on it (event_locator.hpp); after the problem has acted on the
// event (an impact changes y) the run restarts from the new state (FSAL recomputed).
#include "common.hpp"
#include "event_locator.hpp"

#include <cmath>

namespace mbd::integrators {
namespace {

// Butcher tableau (Hairer's DOPRI5).
constexpr double c2 = 1.0 / 5, c3 = 3.0 / 10, c4 = 4.0 / 5, c5 = 8.0 / 9;
constexpr double a21 = 1.0 / 5;
constexpr double a31 = 3.0 / 40, a32 = 9.0 / 40;
constexpr double a41 = 44.0 / 45, a42 = -56.0 / 15, a43 = 32.0 / 9;
constexpr double a51 = 19372.0 / 6561, a52 = -25360.0 / 2187, a53 = 64448.0 / 6561, a54 = -212.0 / 729;
constexpr double a61 = 9017.0 / 3168, a62 = -355.0 / 33, a63 = 46732.0 / 5247, a64 = 49.0 / 176,
                 a65 = -5103.0 / 18656;
constexpr double a71 = 35.0 / 384, a73 = 500.0 / 1113, a74 = 125.0 / 192, a75 = -2187.0 / 6784, a76 = 11.0 / 84;
// error coefficients: 5th minus 4th order weights
constexpr double e1 = 71.0 / 57600, e3 = -71.0 / 16695, e4 = 71.0 / 1920, e5 = -17253.0 / 339200, e6 = 22.0 / 525,
                 e7 = -1.0 / 40;
// continuous extension
constexpr double d1 = -12715105075.0 / 11282082432, d3 = 87487479700.0 / 32700410799,
                 d4 = -10690763975.0 / 1880347072, d5 = 701980252875.0 / 199316789632,
                 d6 = -1453857185.0 / 822651844, d7 = 69997945.0 / 29380423;

class Dopri5 final : public AdaptiveIntegrator {
public:
    using AdaptiveIntegrator::AdaptiveIntegrator;
    std::string name() const override { return "dopri5"; }
    bool locates_events() const override { return true; }

    void integrate(OdeProblem& problem, double t0, Eigen::VectorXd& y, const std::vector<double>& output_times,
                   const OutputCallback& output, IntegratorStats& stats) override;

private:
    double error_norm(const Eigen::VectorXd& y0, const Eigen::VectorXd& y1, const Eigen::VectorXd& err) const {
        const double tol = settings_.tolerance;
        double sum = 0.0;
        for (Eigen::Index i = 0; i < y0.size(); ++i) {
            const double sk = tol + tol * std::max(std::abs(y0[i]), std::abs(y1[i]));
            const double r = err[i] / sk;
            sum += r * r;
        }
        return y0.size() ? std::sqrt(sum / static_cast<double>(y0.size())) : 0.0;
    }
    double initial_step(OdeProblem& problem, double t, const Eigen::VectorXd& y, double hmax, IntegratorStats& stats);
    // Stops the run when the step has collapsed or the attempts exceed settings.max_steps.
    void check_progress(double t, double h, double span, long attempts) const;
    // The stages of a step of size h from (t, y) ending at t_new: the 5th-order
    // solution in y1_, the stage derivatives in k1_..k7_. Returns the norm of the
    // embedded error estimate (1e10 when it is not finite).
    double attempt(OdeProblem& problem, double t, double h, double t_new, const Eigen::VectorXd& y,
                   IntegratorStats& stats);
    // Output at the output times inside (t, t_new) from the continuous extension of
    // the accepted step; false when the callback stopped the run (y is then that output).
    bool emit_inside_step(OdeProblem& problem, double t, double h, double t_new, double eps,
                          const std::vector<double>& output_times, size_t& next, const OutputCallback& output,
                          Eigen::VectorXd& y);
    // The continuous extension of the step of size h from y (after attempt): coefficients
    // r1_..r5_, and its value at the step fraction theta.
    void dense_coefficients(const Eigen::VectorXd& y, double h);
    void dense_at(double theta, Eigen::VectorXd& out) const {
        const double theta1 = 1.0 - theta;
        out = r1_ + theta * (r2_ + theta1 * (r3_ + theta * (r4_ + theta1 * r5_)));
    }
    // Takes the accepted step: y <- y1_, FSAL, blow-up guard, projection.
    void accept(OdeProblem& problem, double t_new, Eigen::VectorXd& y, const BlowUpGuard& guard,
                IntegratorStats& stats);

    Eigen::VectorXd k1_, k2_, k3_, k4_, k5_, k6_, k7_, tmp_, y1_, err_, unprojected_;
    Eigen::VectorXd r1_, r2_, r3_, r4_, r5_, yout_;
    EventLocator events_;
};

double Dopri5::initial_step(OdeProblem& problem, double t, const Eigen::VectorXd& y, double hmax,
                            IntegratorStats& stats) {
    // Hairer's HINIT: an explicit Euler step of guessed size, then h ~ (0.01 / max(|f|, |f'|))^(1/5).
    const double tol = settings_.tolerance;
    const double n = std::max<double>(1.0, static_cast<double>(y.size()));
    double dnf = 0.0, dny = 0.0;
    for (Eigen::Index i = 0; i < y.size(); ++i) {
        const double sk = tol + tol * std::abs(y[i]);
        dnf += (k1_[i] / sk) * (k1_[i] / sk);
        dny += (y[i] / sk) * (y[i] / sk);
    }
    dnf /= n;
    dny /= n;
    double h = (dnf <= 1e-10 || dny <= 1e-10) ? 1e-6 : std::sqrt(dny / dnf) * 0.01;
    h = std::min(h, hmax);
    tmp_ = y + h * k1_;
    problem.rhs(t + h, tmp_, k2_);
    ++stats.rhs_evaluations;
    double der2 = 0.0;
    for (Eigen::Index i = 0; i < y.size(); ++i) {
        const double sk = tol + tol * std::abs(y[i]);
        const double d = (k2_[i] - k1_[i]) / sk;
        der2 += d * d;
    }
    der2 = std::sqrt(der2 / n) / h;
    const double der12 = std::max(std::abs(der2), std::sqrt(dnf));
    const double h1 = der12 <= 1e-15 ? std::max(1e-6, h * 1e-3) : std::pow(0.01 / der12, 0.2);
    if (!std::isfinite(h1)) return std::min(h, hmax);
    return std::min({100.0 * h, h1, hmax});
}

void Dopri5::check_progress(double t, double h, double span, long attempts) const {
    const double scale = std::max(std::abs(t), span);
    if (h < settings_.min_step * scale)
        throw DynamicsError(t, "step size collapse at t = " + format_time(t) + " (h = " + format_time(h) +
                                   "): the problem is too stiff for an explicit integrator or the motion is "
                                   "singular; try --integrator generalized_alpha or cvode");
    if (attempts > settings_.max_steps)
        throw DynamicsError(t, "dopri5: the maximum number of steps (" + std::to_string(settings_.max_steps) +
                                   ") was exceeded at t = " + format_time(t) +
                                   "; the problem may be stiff (try --integrator cvode or generalized_alpha)");
}

double Dopri5::attempt(OdeProblem& problem, double t, double h, double t_new, const Eigen::VectorXd& y,
                       IntegratorStats& stats) {
    tmp_ = y + h * a21 * k1_;
    problem.rhs(t + c2 * h, tmp_, k2_);
    tmp_ = y + h * (a31 * k1_ + a32 * k2_);
    problem.rhs(t + c3 * h, tmp_, k3_);
    tmp_ = y + h * (a41 * k1_ + a42 * k2_ + a43 * k3_);
    problem.rhs(t + c4 * h, tmp_, k4_);
    tmp_ = y + h * (a51 * k1_ + a52 * k2_ + a53 * k3_ + a54 * k4_);
    problem.rhs(t + c5 * h, tmp_, k5_);
    tmp_ = y + h * (a61 * k1_ + a62 * k2_ + a63 * k3_ + a64 * k4_ + a65 * k5_);
    problem.rhs(t_new, tmp_, k6_);
    y1_ = y + h * (a71 * k1_ + a73 * k3_ + a74 * k4_ + a75 * k5_ + a76 * k6_);
    problem.rhs(t_new, y1_, k7_);
    stats.rhs_evaluations += 6;
    err_ = h * (e1 * k1_ + e3 * k3_ + e4 * k4_ + e5 * k5_ + e6 * k6_ + e7 * k7_);
    const double err = error_norm(y, y1_, err_);
    return std::isfinite(err) ? err : 1e10;
}

bool Dopri5::emit_inside_step(OdeProblem& problem, double t, double h, double t_new, double eps,
                              const std::vector<double>& output_times, size_t& next, const OutputCallback& output,
                              Eigen::VectorXd& y) {
    bool have_dense = false;
    while (next < output_times.size() && output_times[next] < t_new - eps) {
        if (!have_dense) {
            dense_coefficients(y, h);
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

void Dopri5::dense_coefficients(const Eigen::VectorXd& y, double h) {
    r1_ = y;
    r2_ = y1_ - y;
    r3_ = h * k1_ - r2_;
    r4_ = r2_ - h * k7_ - r3_;
    r5_ = h * (d1 * k1_ + d3 * k3_ + d4 * k4_ + d5 * k5_ + d6 * k6_ + d7 * k7_);
}

void Dopri5::accept(OdeProblem& problem, double t_new, Eigen::VectorXd& y, const BlowUpGuard& guard,
                    IntegratorStats& stats) {
    y.swap(y1_);
    k1_.swap(k7_);  // FSAL
    guard.check(t_new, y);
    unprojected_ = y;
    project_or_throw(problem, t_new, y);
    stop_if_interrupted(t_new);  // a step boundary: SIGINT/SIGTERM/SIGHUP stop here
    // a re-selection (Formulation::state_redefined) always restarts it too
    const bool redefined = problem.state_redefined();
    if (redefined || y != unprojected_) {
        problem.rhs(t_new, y, k1_);  // restart the FSAL derivative at the projected state
        ++stats.rhs_evaluations;
    }
}

void Dopri5::integrate(OdeProblem& problem, double t0, Eigen::VectorXd& y, const std::vector<double>& output_times,
                       const OutputCallback& output, IntegratorStats& stats) {
    size_t next = open_adaptive_run(name(), settings_, problem, t0, y, output_times, output);
    if (next == output_times.size()) return;
    for (Eigen::VectorXd* v : {&k1_, &k2_, &k3_, &k4_, &k5_, &k6_, &k7_, &tmp_, &y1_, &err_, &unprojected_, &r1_,
                               &r2_, &r3_, &r4_, &r5_, &yout_})
        v->resize(problem.size());

    const double t_end = output_times.back();
    const double eps = time_epsilon(t0, t_end);
    const double span = t_end - t0;
    const double hmax = std::max(span, eps);
    BlowUpGuard guard;
    guard.reset(y);

    double t = t0;
    events_.start(problem, t0, y);
    problem.rhs(t, y, k1_);
    ++stats.rhs_evaluations;
    double h = settings_.step > 0.0 ? std::min(settings_.step, hmax) : initial_step(problem, t, y, hmax, stats);

    // PI controller constants (Hairer's DOPRI5 defaults)
    constexpr double safe = 0.9, facc1 = 1.0 / 0.2, facc2 = 1.0 / 10.0, beta = 0.04;
    constexpr double expo1 = 0.2 - beta * 0.75;
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
        const double err = attempt(problem, t, h, t_new, y, stats);
        const double fac11 = std::pow(std::max(err, 1e-300), expo1);
        if (err > 1.0) {
            ++stats.rejected_steps;
            h = h / std::min(facc1, fac11 / safe);
            reject = true;
            continue;
        }
        double fac = fac11 / std::pow(facold, beta);
        fac = std::max(facc2, std::min(facc1, fac / safe));
        double h_new = h / fac;
        facold = std::max(err, 1e-4);
        if (reject) h_new = std::min(h_new, h);
        double t_step = t_new, h_step = h;  // the step taken: shortened to end on an event
        const bool at_event = events_.active() && events_.left_side(problem, t_new, y1_);
        if (at_event) {
            dense_coefficients(y, h);
            const double theta = events_.locate(problem, t, h, [&](double th, Eigen::VectorXd& out) { dense_at(th, out); });
            h_step = theta * h;
            t_step = t + h_step;
            attempt(problem, t, h_step, t_step, y, stats);  // shorter than the accepted step: within tolerance
        }
        ++stats.steps;
        if (!emit_inside_step(problem, t, h_step, t_step, eps, output_times, next, output, y)) return;
        accept(problem, t_step, y, guard, stats);
        t = t_step;
        if (at_event && events_.handle(problem, t, y, stats)) {
            problem.rhs(t, y, k1_);  // the impact changed y: restart the FSAL derivative there
            ++stats.rhs_evaluations;
        }
        if (!emit_outputs_up_to(t + eps, y, output_times, next, output)) return;
        reject = false;
        h = std::min(h_new, hmax);
    }
}

}  // namespace

std::unique_ptr<Integrator> make_dopri5(const IntegratorSettings& settings) {
    return std::make_unique<Dopri5>(settings);
}

}  // namespace mbd::integrators
