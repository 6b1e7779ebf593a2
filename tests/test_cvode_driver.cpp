// The cvode driver (core/src/integrators/cvode.cpp, cvode_dense_lu.cpp) against oracles
// that do not come from its own output:
//   a stiff linear system y' = A y, A = V D V^-1 with eigenvalues from -1 to -1e4: the
//     closed form y(t) = V exp(D t) V^-1 y0 (the Newton matrices I - gamma A are factored
//     by the driver's own dense LU, so a wrong factorization or solve shows here);
//   a pendulum in Cartesian coordinates with its projection onto the circle: a problem
//     that never redefines its state is projected once per step attempt (inside CVODE),
//     and the projection after each step that a redefining problem gets changes nothing
//     on it (the two runs agree to round-off); the energy is conserved to the tolerance.
#include <mbd/integrator.hpp>

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <cstdio>
#include <vector>

namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

std::vector<double> grid(double t_end, int n) {
    std::vector<double> out;
    for (int k = 1; k <= n; ++k) out.push_back(t_end * k / n);
    return out;
}

struct CvodeRun {
    std::vector<VectorXd> y;
    mbd::IntegratorStats stats;
};

CvodeRun integrate(mbd::OdeProblem& problem, double tolerance, VectorXd y0, const std::vector<double>& outputs) {
    mbd::IntegratorSettings settings;
    settings.tolerance = tolerance;
    CvodeRun r;
    mbd::make_integrator("cvode", settings)->integrate(problem, 0.0, y0, outputs,
                                                        [&](double, const VectorXd& y) {
                                                            r.y.push_back(y);
                                                            return true;
                                                        },
                                                        r.stats);
    return r;
}

class LinearProblem : public mbd::OdeProblem {
public:
    explicit LinearProblem(const MatrixXd& A) : A_(A) {}
    int size() const override { return static_cast<int>(A_.rows()); }
    void rhs(double, const VectorXd& y, VectorXd& ydot) override { ydot.noalias() = A_ * y; }
    bool project(double, VectorXd&) override { return true; }

private:
    MatrixXd A_;
};

// x'' = -lambda x, y'' = -g - lambda y on the unit circle, lambda = (|v|^2 - g y) / |r|^2
// (the multiplier that keeps d2/dt2 |r|^2 = 0); the projection scales r to unit length and
// removes the radial velocity.
class CartesianPendulum : public mbd::OdeProblem {
public:
    static constexpr double g = 9.81;
    explicit CartesianPendulum(bool may_redefine) : may_redefine_(may_redefine) {}
    int size() const override { return 4; }
    void rhs(double, const VectorXd& s, VectorXd& f) override {
        const double lambda = (s[2] * s[2] + s[3] * s[3] - g * s[1]) / (s[0] * s[0] + s[1] * s[1]);
        f.resize(4);
        f << s[2], s[3], -lambda * s[0], -g - lambda * s[1];
    }
    bool project(double, VectorXd& s) override {
        ++projections;
        const Eigen::Vector2d r = s.head<2>().normalized();
        const Eigen::Vector2d v = s.tail<2>();
        s.head<2>() = r;
        s.tail<2>() = v - r * r.dot(v);
        return true;
    }
    bool may_redefine_state() const override { return may_redefine_; }
    static double energy(const VectorXd& s) { return 0.5 * s.tail<2>().squaredNorm() + g * s[1]; }
    long projections = 0;

private:
    bool may_redefine_;
};

}  // namespace

TEST(CvodeDriver, StiffLinearSystemMatchesTheClosedForm) {
    const int n = 8;
    VectorXd d(n);
    d << -1.0, -1e4, -3.0, -1e3, -10.0, -100.0, -2.0, -30.0;
    MatrixXd V(n, n);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) V(i, j) = (i == j ? 2.0 : 0.0) + std::sin(1.0 + 3.0 * i + 7.0 * j);
    const MatrixXd Vinv = V.inverse();
    const MatrixXd A = V * d.asDiagonal() * Vinv;
    VectorXd y0(n);
    for (int i = 0; i < n; ++i) y0[i] = 1.0 + 0.5 * i;
    const VectorXd c = Vinv * y0;
    LinearProblem problem(A);
    const std::vector<double> outputs = grid(2.0, 40);
    for (double tol : {1e-6, 1e-9}) {
        const CvodeRun r = integrate(problem, tol, y0, outputs);
        ASSERT_EQ(r.y.size(), outputs.size());
        double worst = 0.0;
        for (size_t k = 0; k < outputs.size(); ++k) {
            const VectorXd exact = V * (d * outputs[k]).array().exp().matrix().cwiseProduct(c);
            worst = std::max(worst, (r.y[k] - exact).lpNorm<Eigen::Infinity>() / (1.0 + exact.lpNorm<Eigen::Infinity>()));
        }
        std::printf("stiff linear n = %d, tol %.0e: %ld steps, %ld rhs, %ld jacobians, %ld newton; worst error %.2e\n", n,
                    tol, r.stats.steps, r.stats.rhs_evaluations, r.stats.jacobian_evaluations,
                    r.stats.newton_iterations, worst);
        EXPECT_LT(worst, 20.0 * tol);  // a BDF global error: a small multiple of the local tolerance
        EXPECT_GT(r.stats.jacobian_evaluations, 0);
        // stiff (|lambda| h >> 1 at the end): an explicit method would need ~1e4 steps here
        EXPECT_LT(r.stats.steps, 2000);
    }
}

TEST(CvodeDriver, ProjectsOncePerStepUnlessTheProblemMayRedefineItsState) {
    VectorXd y0(4);
    y0 << std::sin(1.2), -std::cos(1.2), 0.0, 0.0;  // released at 1.2 rad from the bottom
    const std::vector<double> outputs = grid(3.0, 30);
    const double tol = 1e-8;
    CartesianPendulum once(false), twice(true);
    const CvodeRun a = integrate(once, tol, y0, outputs);
    const CvodeRun b = integrate(twice, tol, y0, outputs);
    ASSERT_EQ(a.y.size(), outputs.size());
    ASSERT_EQ(b.y.size(), outputs.size());
    std::printf("cartesian pendulum tol %.0e: %ld steps, %ld rejected; projections %ld (may not redefine), %ld (may)\n",
                tol, a.stats.steps, a.stats.rejected_steps, once.projections, twice.projections);
    // inside CVODE: once per step attempt whose Newton iteration converged
    EXPECT_GE(once.projections, a.stats.steps);
    EXPECT_LE(once.projections, a.stats.steps + a.stats.rejected_steps);
    // a problem that may redefine its state is projected again after every step and output
    EXPECT_EQ(b.stats.steps, a.stats.steps);
    EXPECT_GE(twice.projections, once.projections + b.stats.steps + static_cast<long>(outputs.size()));
    const double e0 = CartesianPendulum::energy(y0);
    double difference = 0.0, drift = 0.0, energy = 0.0;
    for (size_t k = 0; k < outputs.size(); ++k) {
        difference = std::max(difference, (a.y[k] - b.y[k]).lpNorm<Eigen::Infinity>());
        drift = std::max(drift, std::abs(a.y[k].head<2>().norm() - 1.0));
        energy = std::max(energy, std::abs(CartesianPendulum::energy(a.y[k]) - e0));
    }
    std::printf("  max |y_once - y_twice| %.2e, max ||r| - 1| %.2e, max |E - E0| %.2e\n", difference, drift, energy);
    EXPECT_LT(difference, 1e-13);  // the second projection of a projected state is round-off
    EXPECT_LT(drift, 1e-14);       // the outputs are projected step ends
    // |dE| <= (|v| + g) max(|dr|, |dv|), with a BDF global error of ~20 tol on each
    const double v_max = std::sqrt(2.0 * CartesianPendulum::g * (1.0 - std::cos(1.2)));
    EXPECT_LT(energy, (v_max + CartesianPendulum::g) * 20.0 * tol * (1.0 + v_max));
}
