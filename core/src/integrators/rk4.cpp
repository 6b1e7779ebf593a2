// Classical fourth-order Runge-Kutta, fixed step (book Sec. 6.11, L9175-9188):
//   k1 = f(t, y), k2 = f(t + h/2, y + h/2 k1), k3 = f(t + h/2, y + h/2 k2),
//   k4 = f(t + h, y + h k3), y_{n+1} = y_n + h/6 (k1 + 2 k2 + 2 k3 + k4).
#include "common.hpp"

namespace mbd::integrators {
namespace {

class Rk4 final : public FixedStepIntegrator {
public:
    using FixedStepIntegrator::FixedStepIntegrator;

private:
    void prepare(int n) override {
        for (Eigen::VectorXd* v : {&k1_, &k2_, &k3_, &k4_, &tmp_}) v->resize(n);
    }
    void step(OdeProblem& problem, double t, double h, Eigen::VectorXd& y, IntegratorStats& stats) override {
        problem.rhs(t, y, k1_);
        tmp_ = y + (0.5 * h) * k1_;
        problem.rhs(t + 0.5 * h, tmp_, k2_);
        tmp_ = y + (0.5 * h) * k2_;
        problem.rhs(t + 0.5 * h, tmp_, k3_);
        tmp_ = y + h * k3_;
        problem.rhs(t + h, tmp_, k4_);
        stats.rhs_evaluations += 4;
        y += (h / 6.0) * (k1_ + 2.0 * k2_ + 2.0 * k3_ + k4_);
    }

    Eigen::VectorXd k1_, k2_, k3_, k4_, tmp_;
};

}  // namespace

std::unique_ptr<Integrator> make_rk4(const IntegratorSettings& settings) { return std::make_unique<Rk4>(settings); }

}  // namespace mbd::integrators
