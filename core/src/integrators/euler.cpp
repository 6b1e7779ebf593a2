// Explicit (forward) Euler, fixed step: y_{n+1} = y_n + h f(t_n, y_n)
// (book Eq. 6.163). A teaching integrator: first order, only for checks.
#include "common.hpp"

namespace mbd::integrators {
namespace {

class Euler final : public Integrator {
public:
    explicit Euler(const IntegratorSettings& settings) : settings_(settings) {}
    std::string name() const override { return "euler"; }
    bool adaptive() const override { return false; }

    void integrate(OdeProblem& problem, double t0, Eigen::VectorXd& y, const std::vector<double>& output_times,
                   const OutputCallback& output, IntegratorStats& stats) override {
        f_.resize(problem.size());
        fixed_step_run(name(), settings_, problem, t0, y, output_times, output, stats,
                       [&](double t, double h, Eigen::VectorXd& state) {
                           problem.rhs(t, state, f_);
                           ++stats.rhs_evaluations;
                           state += h * f_;
                       });
    }

private:
    IntegratorSettings settings_;
    Eigen::VectorXd f_;
};

}  // namespace

std::unique_ptr<Integrator> make_euler(const IntegratorSettings& settings) { return std::make_unique<Euler>(settings); }

}  // namespace mbd::integrators
