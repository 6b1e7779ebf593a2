// Explicit (forward) Euler, fixed step: y_{n+1} = y_n + h f(t_n, y_n)
// (book Eq. 6.163). A teaching integrator: first order, only for checks.
#include "common.hpp"

namespace mbd::integrators {
namespace {

class Euler final : public FixedStepIntegrator {
public:
    using FixedStepIntegrator::FixedStepIntegrator;

private:
    void prepare(int n) override { f_.resize(n); }
    void step(OdeProblem& problem, double t, double h, Eigen::VectorXd& y, IntegratorStats& stats) override {
        problem.rhs(t, y, f_);
        ++stats.rhs_evaluations;
        y += h * f_;
    }

    Eigen::VectorXd f_;
};

}  // namespace

std::unique_ptr<Integrator> make_euler(const IntegratorSettings& settings) { return std::make_unique<Euler>(settings); }

}  // namespace mbd::integrators
