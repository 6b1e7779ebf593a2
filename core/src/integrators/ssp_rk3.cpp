// Third-order strong-stability-preserving Runge-Kutta (SSP-RK3), fixed step: Shu and Osher's
// scheme (J. Comput. Phys. 77, 1988, Eq. 2.18), each stage a convex combination of forward
// Euler steps, so any bound forward Euler keeps at step h (a norm, a positivity) it keeps too:
//   u1 = y_n + h f(t, y_n)
//   u2 = 3/4 y_n + 1/4 (u1 + h f(t + h, u1))
//   y_{n+1} = 1/3 y_n + 2/3 (u2 + h f(t + h/2, u2)).
#include "common.hpp"

namespace mbd::integrators {
namespace {

class SspRk3 final : public FixedStepIntegrator {
public:
    using FixedStepIntegrator::FixedStepIntegrator;

private:
    void prepare(int n) override {
        for (Eigen::VectorXd* v : {&f_, &u1_, &u2_}) v->resize(n);
    }
    void step(OdeProblem& problem, double t, double h, Eigen::VectorXd& y, IntegratorStats& stats) override {
        problem.rhs(t, y, f_);
        u1_ = y + h * f_;
        problem.rhs(t + h, u1_, f_);
        u2_ = 0.75 * y + 0.25 * (u1_ + h * f_);
        problem.rhs(t + 0.5 * h, u2_, f_);
        stats.rhs_evaluations += 3;
        y = (1.0 / 3.0) * y + (2.0 / 3.0) * (u2_ + h * f_);
    }

    Eigen::VectorXd f_, u1_, u2_;
};

}  // namespace

std::unique_ptr<Integrator> make_ssp_rk3(const IntegratorSettings& settings) {
    return std::make_unique<SspRk3>(settings);
}

}  // namespace mbd::integrators
