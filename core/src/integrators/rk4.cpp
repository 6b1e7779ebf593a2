// Classical fourth-order Runge-Kutta, fixed step (book Sec. 6.11, L9175-9188):
//   k1 = f(t, y), k2 = f(t + h/2, y + h/2 k1), k3 = f(t + h/2, y + h/2 k2),
//   k4 = f(t + h, y + h k3), y_{n+1} = y_n + h/6 (k1 + 2 k2 + 2 k3 + k4).
#include "common.hpp"

namespace mbd::integrators {
namespace {

class Rk4 final : public Integrator {
public:
    explicit Rk4(const IntegratorSettings& settings) : settings_(settings) {}
    std::string name() const override { return "rk4"; }
    bool adaptive() const override { return false; }

    void integrate(OdeProblem& problem, double t0, Eigen::VectorXd& y, const std::vector<double>& output_times,
                   const OutputCallback& output, IntegratorStats& stats) override {
        const int n = problem.size();
        k1_.resize(n);
        k2_.resize(n);
        k3_.resize(n);
        k4_.resize(n);
        tmp_.resize(n);
        fixed_step_run(name(), settings_, problem, t0, y, output_times, output, stats,
                       [&](double t, double h, Eigen::VectorXd& state) {
                           problem.rhs(t, state, k1_);
                           tmp_ = state + (0.5 * h) * k1_;
                           problem.rhs(t + 0.5 * h, tmp_, k2_);
                           tmp_ = state + (0.5 * h) * k2_;
                           problem.rhs(t + 0.5 * h, tmp_, k3_);
                           tmp_ = state + h * k3_;
                           problem.rhs(t + h, tmp_, k4_);
                           stats.rhs_evaluations += 4;
                           state += (h / 6.0) * (k1_ + 2.0 * k2_ + 2.0 * k3_ + k4_);
                       });
    }

private:
    IntegratorSettings settings_;
    Eigen::VectorXd k1_, k2_, k3_, k4_, tmp_;
};

}  // namespace

std::unique_ptr<Integrator> make_rk4(const IntegratorSettings& settings) { return std::make_unique<Rk4>(settings); }

}  // namespace mbd::integrators
