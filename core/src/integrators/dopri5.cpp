// Dormand-Prince 5(4) (Dormand & Prince 1980; Hairer, Norsett & Wanner,
// "Solving Ordinary Differential Equations I", 2nd ed., Sec. II.4-II.6, code DOPRI5):
// seven stages with FSAL, local extrapolation (the 5th-order solution is kept),
// the embedded 4th-order error estimate, Hairer's PI step-size controller
// (beta = 0.04) and the 4th-order continuous extension for output between steps.
// The step control, output, events and projection are the shared driver's
// (embedded_runge_kutta.hpp).
#include "embedded_runge_kutta.hpp"

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

// Hairer's DOPRI5 defaults: beta = 0.04, err^(1/5 - 0.75 beta), ratio in [0.2, 10].
constexpr StepControl kControl{0.2 - 0.04 * 0.75, 0.04, 0.9, 0.2, 10.0, 5};

class Dopri5 final : public EmbeddedRungeKutta {
public:
    explicit Dopri5(const IntegratorSettings& settings) : EmbeddedRungeKutta(settings, kControl) {}

private:
    void prepare(int n) override {
        for (Eigen::VectorXd* v : {&k2_, &k3_, &k4_, &k5_, &k6_, &tmp_, &err_, &r1_, &r2_, &r3_, &r4_, &r5_})
            v->resize(n);
    }
    double attempt(OdeProblem& problem, double t, double h, double t_new, const Eigen::VectorXd& y,
                   IntegratorStats& stats) override;
    void dense_coefficients(OdeProblem& problem, double t, double h, const Eigen::VectorXd& y,
                            IntegratorStats& stats) override;
    void dense_at(double theta, Eigen::VectorXd& out) const override {
        const double theta1 = 1.0 - theta;
        out = r1_ + theta * (r2_ + theta1 * (r3_ + theta * (r4_ + theta1 * r5_)));
    }

    // k1 is f0_ and k7 (FSAL, the derivative at the step's end) f1_
    Eigen::VectorXd k2_, k3_, k4_, k5_, k6_, tmp_, err_;
    Eigen::VectorXd r1_, r2_, r3_, r4_, r5_;
};

double Dopri5::attempt(OdeProblem& problem, double t, double h, double t_new, const Eigen::VectorXd& y,
                       IntegratorStats& stats) {
    const Eigen::VectorXd& k1 = f0_;
    tmp_ = y + h * a21 * k1;
    problem.rhs(t + c2 * h, tmp_, k2_);
    tmp_ = y + h * (a31 * k1 + a32 * k2_);
    problem.rhs(t + c3 * h, tmp_, k3_);
    tmp_ = y + h * (a41 * k1 + a42 * k2_ + a43 * k3_);
    problem.rhs(t + c4 * h, tmp_, k4_);
    tmp_ = y + h * (a51 * k1 + a52 * k2_ + a53 * k3_ + a54 * k4_);
    problem.rhs(t + c5 * h, tmp_, k5_);
    tmp_ = y + h * (a61 * k1 + a62 * k2_ + a63 * k3_ + a64 * k4_ + a65 * k5_);
    problem.rhs(t_new, tmp_, k6_);
    y1_ = y + h * (a71 * k1 + a73 * k3_ + a74 * k4_ + a75 * k5_ + a76 * k6_);
    problem.rhs(t_new, y1_, f1_);
    stats.rhs_evaluations += 6;
    err_ = h * (e1 * k1 + e3 * k3_ + e4 * k4_ + e5 * k5_ + e6 * k6_ + e7 * f1_);
    double sum = 0.0;
    for (Eigen::Index i = 0; i < y.size(); ++i) {
        const double r = err_[i] / scale(y, y1_, i);
        sum += r * r;
    }
    return y.size() ? std::sqrt(sum / static_cast<double>(y.size())) : 0.0;
}

void Dopri5::dense_coefficients(OdeProblem&, double, double h, const Eigen::VectorXd& y, IntegratorStats&) {
    r1_ = y;
    r2_ = y1_ - y;
    r3_ = h * f0_ - r2_;
    r4_ = r2_ - h * f1_ - r3_;
    r5_ = h * (d1 * f0_ + d3 * k3_ + d4 * k4_ + d5 * k5_ + d6 * k6_ + d7 * f1_);
}

}  // namespace

std::unique_ptr<Integrator> make_dopri5(const IntegratorSettings& settings) {
    return std::make_unique<Dopri5>(settings);
}

}  // namespace mbd::integrators
