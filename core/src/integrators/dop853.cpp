// DOP853: the explicit Runge-Kutta pair of order 8 of Dormand & Prince, after Hairer,
// Norsett & Wanner, "Solving Ordinary Differential Equations I", 2nd ed., Sec. II.5,
// II.6 and II.10 (their code DOP853); coefficients in dop853_tableau.hpp.
// Twelve stages per step (FSAL: f at the step's end is the next step's first stage),
// local extrapolation (the 8th-order solution is kept), the error estimate of DOP853
// that combines the embedded 5th- and 3rd-order differences, and the 7th-order
// continuous extension (three more stages, evaluated only in steps that need it: an
// output time inside the step, or an event to locate). The step control, output, events
// and projection are the shared driver's (embedded_runge_kutta.hpp).
#include "dop853_tableau.hpp"
#include "embedded_runge_kutta.hpp"

#include <cmath>

namespace mbd::integrators {
namespace {

// Hairer's DOP853 defaults: beta = 0, err^(1/8), step ratio in [0.333, 6].
constexpr StepControl kControl{1.0 / 8.0, 0.0, 0.9, 0.333, 6.0, 8};

class Dop853 final : public EmbeddedRungeKutta {
public:
    explicit Dop853(const IntegratorSettings& settings) : EmbeddedRungeKutta(settings, kControl) {}

private:
    void prepare(int n) override {
        for (Eigen::VectorXd& v : stages_) v.resize(n);
        for (Eigen::VectorXd& v : r_) v.resize(n);
        for (Eigen::VectorXd* v : {&tmp_, &bk_, &err5_}) v->resize(n);
    }
    double attempt(OdeProblem& problem, double t, double h, double t_new, const Eigen::VectorXd& y,
                   IntegratorStats& stats) override;
    void end_derivative(OdeProblem& problem, double t_new, IntegratorStats& stats) override {
        problem.rhs(t_new, y1_, f1_);
        ++stats.rhs_evaluations;
    }
    void dense_coefficients(OdeProblem& problem, double t, double h, const Eigen::VectorXd& y,
                            IntegratorStats& stats) override;
    void dense_at(double s, Eigen::VectorXd& out) const override {
        const double s1 = 1.0 - s;
        out = r_[0] + s * (r_[1] + s1 * (r_[2] + s * (r_[3] + s1 * (r_[4] + s * (r_[5] + s1 * (r_[6] + s * r_[7]))))));
    }

    // Stage i's derivative: 0 is f0_, 12 (f at the step's end) f1_.
    const Eigen::VectorXd& k(int i) const { return i == 0 ? f0_ : i == 12 ? f1_ : stages_[i]; }
    // Evaluates stage i of the step of size h from (t, y) into stages_[i]; t_i is its time.
    void stage(OdeProblem& problem, double t_i, double h, const Eigen::VectorXd& y, int i, IntegratorStats& stats);

    Eigen::VectorXd stages_[dop853::kDenseStages];  // 0 and 12 unused: they are f0_ and f1_
    Eigen::VectorXd r_[8];  // the continuous extension's coefficients
    Eigen::VectorXd tmp_, bk_, err5_;
};

void Dop853::stage(OdeProblem& problem, double t_i, double h, const Eigen::VectorXd& y, int i,
                   IntegratorStats& stats) {
    tmp_ = y;
    for (int j = 0; j < i; ++j)
        if (dop853::a[i][j] != 0.0) tmp_ += (h * dop853::a[i][j]) * k(j);
    problem.rhs(t_i, tmp_, stages_[i]);
    ++stats.rhs_evaluations;
}

double Dop853::attempt(OdeProblem& problem, double t, double h, double t_new, const Eigen::VectorXd& y,
                       IntegratorStats& stats) {
    using namespace dop853;
    for (int i = 1; i < kStages; ++i) stage(problem, c[i] == 1.0 ? t_new : t + c[i] * h, h, y, i, stats);
    // bk = sum b_i k_i (b is row 12 of a), err5 = sum e5_i k_i
    bk_.setZero();
    err5_.setZero();
    for (int i = 0; i < kStages; ++i) {
        if (a[12][i] != 0.0) bk_ += a[12][i] * k(i);
        if (e5[i] != 0.0) err5_ += e5[i] * k(i);
    }
    y1_ = y + h * bk_;
    // Hairer's combined estimate: err5^2 / sqrt(err5^2 + 0.01 err3^2), of order 8 in h
    // (the 5th-order difference scaled by the ratio of the 5th- to the 3rd-order one)
    const Eigen::VectorXd &k0 = k(kBhhStage[0]), &k8 = k(kBhhStage[1]), &k11 = k(kBhhStage[2]);
    double sum5 = 0.0, sum3 = 0.0;
    for (Eigen::Index n = 0; n < y.size(); ++n) {
        const double sk = scale(y, y1_, n);
        const double e3 = bk_[n] - bhh[0] * k0[n] - bhh[1] * k8[n] - bhh[2] * k11[n];
        sum3 += (e3 / sk) * (e3 / sk);
        sum5 += (err5_[n] / sk) * (err5_[n] / sk);
    }
    if (y.size() == 0) return 0.0;
    double deno = sum5 + 0.01 * sum3;
    if (deno <= 0.0) deno = 1.0;
    return std::abs(h) * sum5 * std::sqrt(1.0 / (static_cast<double>(y.size()) * deno));
}

void Dop853::dense_coefficients(OdeProblem& problem, double t, double h, const Eigen::VectorXd& y,
                                IntegratorStats& stats) {
    using namespace dop853;
    for (int i = 13; i < kDenseStages; ++i) stage(problem, t + c[i] * h, h, y, i, stats);
    r_[0] = y;
    r_[1] = y1_ - y;
    r_[2] = h * f0_ - r_[1];
    r_[3] = r_[1] - h * f1_ - r_[2];
    for (int m = 0; m < 4; ++m) {
        Eigen::VectorXd& r = r_[4 + m];
        r.setZero();
        for (int i = 0; i < kDenseStages; ++i)
            if (d[m][i] != 0.0) r += (h * d[m][i]) * k(i);
    }
}

}  // namespace

std::unique_ptr<Integrator> make_dop853(const IntegratorSettings& settings) {
    return std::make_unique<Dop853>(settings);
}

}  // namespace mbd::integrators
