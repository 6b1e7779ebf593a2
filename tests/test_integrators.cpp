// Time integrators (core/src/integrators/) against independent oracles:
//   Ex. 6.12 (book, Sec. 6.11): three explicit Euler steps and one RK4 step of the
//     driven pendulum f(y, t) = [y2, 30 sin 5t - 14.715 cos y1] (digest 11.9-11.10,
//     with the digest's corrected RK4 exponent);
//   closed-form solutions of smooth ODEs (order of RK4, DOPRI5 tolerance and dense
//     output, CVODE tolerance);
//   a mass on a spring with k = 1e8 (explicit methods unstable or slow, the implicit
//     generalized-alpha stable, energy from the closed-form expression);
//   a pendulum through the real scene loader and ModelSystem, integrated as an
//     index-3 DAE by generalized_alpha and compared with the 1-DOF pendulum
//     equation J_O phi'' = -m g c sin(phi) written here.
// No expected number comes from the engine's own output.
#include "support/convergence_order.hpp"
#include "support/function_problem.hpp"
#include "support/test_support.hpp"

#include <mbd/integrator.hpp>
#include <mbd/model_system.hpp>
#include <mbd/scene.hpp>
#include <mbd/simulation.hpp>
#include <mbd/kit/formulation.hpp>
#include <mbd/kit/index3_problem.hpp>

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

namespace {

using Eigen::VectorXd;

using mbd::test::FunctionProblem;
using mbd::test::RunResult;
using mbd::test::run;

std::vector<double> grid(double t0, double t1, int n) {
    std::vector<double> out;
    for (int k = 1; k <= n; ++k) out.push_back(t0 + (t1 - t0) * k / n);
    return out;
}

// --- Ex. 6.12: f(y, t) = [y2, 30 sin 5t - 14.715 cos y1]
FunctionProblem ex612() {
    return FunctionProblem(2, [](double t, const VectorXd& y, VectorXd& f) {
        f[0] = y[1];
        f[1] = 30.0 * std::sin(5.0 * t) - 14.715 * std::cos(y[0]);
    });
}

// --- y' = -y + sin t, y(0) = y0: y = (y0 + 1/2) e^-t + (sin t - cos t)/2
double smooth_exact(double t, double y0) { return (y0 + 0.5) * std::exp(-t) + 0.5 * (std::sin(t) - std::cos(t)); }
FunctionProblem smooth() {
    return FunctionProblem(1, [](double t, const VectorXd& y, VectorXd& f) { f[0] = -y[0] + std::sin(t); });
}

// --- harmonic oscillator x'' = -w^2 x, x(0) = 1, x'(0) = 0: x = cos wt
constexpr double kOmega = 2.0;
FunctionProblem oscillator() {
    return FunctionProblem(2, [](double, const VectorXd& y, VectorXd& f) {
        f[0] = y[1];
        f[1] = -kOmega * kOmega * y[0];
    });
}

}  // namespace

// ---------------------------------------------------------------- factory

TEST(IntegratorFactory, KnowsItsIntegratorsAndListsThemForUnknownNames) {
    const std::vector<std::string> names = mbd::integrator_names();
    for (const char* expected : {"euler", "rk4", "dopri5", "dop853", "generalized_alpha", "cvode"}) {
        EXPECT_NE(std::find(names.begin(), names.end(), expected), names.end()) << expected;
        EXPECT_EQ(mbd::make_integrator(expected, {})->name(), expected);
    }
    EXPECT_TRUE(mbd::make_integrator("dopri5", {})->adaptive());
    EXPECT_TRUE(mbd::make_integrator("dop853", {})->adaptive());
    EXPECT_TRUE(mbd::make_integrator("dop853", {})->locates_events());
    EXPECT_FALSE(mbd::make_integrator("rk4", {})->adaptive());
    try {
        mbd::make_integrator("rk45", {});
        FAIL() << "no InputError";
    } catch (const mbd::InputError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("rk45"), std::string::npos) << what;
        for (const std::string& n : names) EXPECT_NE(what.find(n), std::string::npos) << what;
    }
}

// ---------------------------------------------------------------- book Ex. 6.12

TEST(BookEx612, ThreeEulerSteps) {
    FunctionProblem problem = ex612();
    mbd::IntegratorSettings s;
    s.step = 0.01;
    const RunResult r = run("euler", s, problem, 0.0, VectorXd::Zero(2), {0.01, 0.02, 0.03});
    ASSERT_EQ(r.y.size(), 3u);
    // printed values; tolerance: half a unit of the last printed digit
    EXPECT_NEAR(r.y[0][0], 0.0, 1e-15);
    EXPECT_NEAR(r.y[0][1], -0.14715, 5e-9);
    EXPECT_NEAR(r.y[1][0], -0.0014715, 5e-11);
    EXPECT_NEAR(r.y[1][1], -0.279306, 5e-7);
    EXPECT_NEAR(r.y[2][0], -4.26456e-3, 5e-9);
    EXPECT_NEAR(r.y[2][1], -0.396506, 5e-7);
    EXPECT_EQ(r.stats.steps, 3);
    EXPECT_EQ(r.stats.rhs_evaluations, 3);
}

TEST(BookEx612, OneRk4Step) {
    FunctionProblem problem = ex612();
    mbd::IntegratorSettings s;
    s.step = 0.01;
    const RunResult r = run("rk4", s, problem, 0.0, VectorXd::Zero(2), {0.01});
    ASSERT_EQ(r.y.size(), 1u);
    std::printf("RK4 Ex. 6.12 y1 = [%.10e, %.10e]\n", r.y[0][0], r.y[0][1]);
    // digest 11.10: y1 = [-7.10753e-4, -0.1396516] (the book's -0.71075e-4 is a misprint),
    // to half a unit of the last printed digit
    EXPECT_NEAR(r.y[0][0], -7.10753e-4, 5e-10);
    EXPECT_NEAR(r.y[0][1], -0.1396516, 5e-8);
    // the book's stage values (L9191-9232), recomputed here by hand to 1e-12
    const double h = 0.01;
    auto g = [](double t, double y1) { return 30.0 * std::sin(5.0 * t) - 14.715 * std::cos(y1); };
    const double f1a = 0.0, f1b = h * g(0.0, 0.0);                                     // [0, -0.14715]
    const double f2a = h * (f1b / 2), f2b = h * g(h / 2, f1a / 2);                     // [-0.73575e-3, -0.1396508]
    const double f3a = h * (f2b / 2), f3b = h * g(h / 2, f2a / 2);                     // [-0.69825e-3, -0.1396508]
    const double f4a = h * f3b, f4b = h * g(h, f3a);                                   // [-0.1396508e-2, -0.13215621]
    EXPECT_NEAR(f1b, -0.14715, 5e-9);
    EXPECT_NEAR(f2a, -0.73575e-3, 5e-9);
    EXPECT_NEAR(f2b, -0.1396508, 5e-8);
    EXPECT_NEAR(f4b, -0.13215621, 5e-9);
    EXPECT_NEAR(r.y[0][0], (f1a + 2 * f2a + 2 * f3a + f4a) / 6, 1e-12);
    EXPECT_NEAR(r.y[0][1], (f1b + 2 * f2b + 2 * f3b + f4b) / 6, 1e-12);
    // and not the misprinted exponent
    EXPECT_GT(std::abs(r.y[0][0] - (-0.71075e-4)), 1e-4);
    EXPECT_EQ(r.stats.rhs_evaluations, 4);
}

// ---------------------------------------------------------------- smooth problems

TEST(Rk4, FourthOrderOnTheHarmonicOscillator) {
    const double T = 5.0;
    std::vector<double> errors;
    for (double h : {0.1, 0.05, 0.025, 0.0125}) {
        FunctionProblem problem = oscillator();
        mbd::IntegratorSettings s;
        s.step = h;
        VectorXd y0(2);
        y0 << 1.0, 0.0;
        const RunResult r = run("rk4", s, problem, 0.0, y0, {T});
        const double e = std::max(std::abs(r.y.back()[0] - std::cos(kOmega * T)),
                                  std::abs(r.y.back()[1] + kOmega * std::sin(kOmega * T)));
        errors.push_back(e);
    }
    mbd::test::expect_order_under_halving(errors, 3.5, 4.5, "RK4 oscillator");
}

TEST(Rk4, HitsOutputTimesThatAreNotMultiplesOfTheStep) {
    FunctionProblem problem = smooth();
    mbd::IntegratorSettings s;
    s.step = 0.03;
    VectorXd y0(1);
    y0 << 2.0;
    const std::vector<double> outputs = {0.1, 0.25, 0.25, 1.0};
    const RunResult r = run("rk4", s, problem, 0.0, y0, outputs);
    ASSERT_EQ(r.t.size(), outputs.size());
    for (size_t k = 0; k < outputs.size(); ++k) {
        EXPECT_EQ(r.t[k], outputs[k]);
        EXPECT_NEAR(r.y[k][0], smooth_exact(outputs[k], 2.0), 1e-7) << outputs[k];
    }
}

TEST(Dopri5, MeetsTightToleranceAndDenseOutputIsAccurate) {
    FunctionProblem problem = smooth();
    mbd::IntegratorSettings s;
    s.tolerance = 1e-10;
    VectorXd y0(1);
    y0 << 2.0;
    // 997 outputs at irregular times, many more than the steps: most come from the
    // continuous extension
    std::vector<double> outputs;
    for (int k = 1; k <= 997; ++k) outputs.push_back(10.0 * k / 997.0);
    const RunResult r = run("dopri5", s, problem, 0.0, y0, outputs);
    ASSERT_EQ(r.t.size(), outputs.size());
    double worst = 0.0;
    for (size_t k = 0; k < outputs.size(); ++k)
        worst = std::max(worst, std::abs(r.y[k][0] - smooth_exact(outputs[k], 2.0)));
    std::printf("DOPRI5 tol 1e-10: %ld steps, %ld rejected, %ld rhs; worst error over %zu outputs %.3e\n",
                r.stats.steps, r.stats.rejected_steps, r.stats.rhs_evaluations, outputs.size(), worst);
    EXPECT_LT(r.stats.steps, 500);  // so most outputs are interpolated
    EXPECT_LT(worst, 1e-9);
    EXPECT_EQ(r.stats.rhs_evaluations, problem.calls);

    // and the end point alone
    FunctionProblem p2 = smooth();
    const RunResult end = run("dopri5", s, p2, 0.0, y0, {10.0});
    const double e_end = std::abs(end.y.back()[0] - smooth_exact(10.0, 2.0));
    std::printf("DOPRI5 tol 1e-10: end error %.3e in %ld steps\n", e_end, end.stats.steps);
    EXPECT_LT(e_end, 1e-9);
}

TEST(Dopri5, DenseOutputOnTheOscillatorAtLooseTolerance) {
    // At tol 1e-6 the steps are long; outputs between them still match cos(wt) to ~tol.
    FunctionProblem problem = oscillator();
    mbd::IntegratorSettings s;
    s.tolerance = 1e-6;
    VectorXd y0(2);
    y0 << 1.0, 0.0;
    const std::vector<double> outputs = grid(0.0, 3.0, 301);
    const RunResult r = run("dopri5", s, problem, 0.0, y0, outputs);
    double worst = 0.0;
    for (size_t k = 0; k < outputs.size(); ++k) worst = std::max(worst, std::abs(r.y[k][0] - std::cos(kOmega * outputs[k])));
    std::printf("DOPRI5 oscillator tol 1e-6: %ld steps for %zu outputs, worst error %.3e\n", r.stats.steps,
                outputs.size(), worst);
    EXPECT_LT(r.stats.steps, 100);
    EXPECT_LT(worst, 1e-5);
}

// An explicit pair on the unit circle, projected back to |y| = 1 after each step: the invariant
// holds to round-off, the motion to the tolerance's order, and the FSAL derivative restarts.
void projection_keeps_the_invariant(const std::string& name, double tolerance, double bound) {
    long projections = 0;
    FunctionProblem problem(
        2,
        [](double, const VectorXd& y, VectorXd& f) {
            f[0] = -y[1];
            f[1] = y[0];
        },
        [&](double, VectorXd& y) {
            ++projections;
            y.normalize();
            return true;
        });
    mbd::IntegratorSettings s;
    s.tolerance = tolerance;
    VectorXd y0(2);
    y0 << 1.0, 0.0;
    const RunResult r = run(name, s, problem, 0.0, y0, grid(0.0, 20.0, 40));
    ASSERT_EQ(r.t.size(), 40u);
    for (size_t k = 0; k < r.t.size(); ++k) {
        EXPECT_NEAR(r.y[k].norm(), 1.0, 1e-14) << name;
        EXPECT_NEAR(r.y[k][0], std::cos(r.t[k]), bound) << name;
    }
    EXPECT_GE(projections, r.stats.steps) << name;
    EXPECT_EQ(r.stats.rhs_evaluations, problem.calls) << name;
}

TEST(Dopri5, ProjectionKeepsTheInvariantAndRestartsFsal) { projection_keeps_the_invariant("dopri5", 1e-5, 1e-4); }
TEST(Dop853, ProjectionKeepsTheInvariantAndRestartsFsal) { projection_keeps_the_invariant("dop853", 1e-7, 1e-6); }

TEST(Dopri5, StepSizeCollapseIsADynamicsError) {
    // y' = -1/(2y), y(0) = 1: y = sqrt(1 - t) ends at t = 1 with an infinite slope
    FunctionProblem problem(1, [](double, const VectorXd& y, VectorXd& f) { f[0] = -0.5 / y[0]; });
    mbd::IntegratorSettings s;
    s.tolerance = 1e-8;
    VectorXd y0(1);
    y0 << 1.0;
    try {
        run("dopri5", s, problem, 0.0, y0, {2.0});
        FAIL() << "no DynamicsError";
    } catch (const mbd::DynamicsError& e) {
        std::printf("DOPRI5 singular problem: %s\n", e.what());
        EXPECT_NEAR(e.time(), 1.0, 1e-3);
        const std::string what = e.what();
        EXPECT_TRUE(what.find("step size collapse") != std::string::npos ||
                    what.find("non-finite") != std::string::npos)
            << what;
    }
}

TEST(Dopri5, MaxStepsIsADynamicsError) {
    FunctionProblem problem = oscillator();
    mbd::IntegratorSettings s;
    s.tolerance = 1e-8;
    s.max_steps = 20;
    VectorXd y0(2);
    y0 << 1.0, 0.0;
    try {
        run("dopri5", s, problem, 0.0, y0, {100.0});
        FAIL() << "no DynamicsError";
    } catch (const mbd::DynamicsError& e) {
        EXPECT_NE(std::string(e.what()).find("maximum number of steps"), std::string::npos) << e.what();
    }
}

TEST(Cvode, MeetsItsToleranceOnTheSmoothOde) {
    for (double tol : {1e-6, 1e-9}) {
        FunctionProblem problem = smooth();
        mbd::IntegratorSettings s;
        s.tolerance = tol;
        VectorXd y0(1);
        y0 << 2.0;
        const std::vector<double> outputs = grid(0.0, 10.0, 100);
        const RunResult r = run("cvode", s, problem, 0.0, y0, outputs);
        ASSERT_EQ(r.t.size(), outputs.size());
        double worst = 0.0;
        for (size_t k = 0; k < outputs.size(); ++k)
            worst = std::max(worst, std::abs(r.y[k][0] - smooth_exact(outputs[k], 2.0)));
        std::printf("CVODE tol %.0e: %ld steps, %ld rejected, %ld rhs, %ld jac, %ld newton; worst error %.3e\n",
                    tol, r.stats.steps, r.stats.rejected_steps, r.stats.rhs_evaluations,
                    r.stats.jacobian_evaluations, r.stats.newton_iterations, worst);
        // BDF global error: a small multiple of the local tolerance
        EXPECT_LT(worst, 20.0 * tol);
        EXPECT_GT(r.stats.steps, 0);
        EXPECT_GT(r.stats.newton_iterations, 0);
    }
}

TEST(Cvode, RhsErrorsPropagateAsDynamicsError) {
    FunctionProblem problem(1, [](double t, const VectorXd& y, VectorXd& f) {
        if (t > 0.5) throw mbd::DynamicsError(t, "singular saddle point (test)");
        f[0] = -y[0];
    });
    VectorXd y0(1);
    y0 << 1.0;
    try {
        run("cvode", {}, problem, 0.0, y0, {1.0});
        FAIL() << "no DynamicsError";
    } catch (const mbd::DynamicsError& e) {
        EXPECT_NE(std::string(e.what()).find("singular saddle point (test)"), std::string::npos) << e.what();
        EXPECT_GT(e.time(), 0.5);
    }
}

// ---------------------------------------------------------------- stiff spring, k = 1e8

namespace {

constexpr double kStiff = 1e8;
FunctionProblem stiff_spring() {
    return FunctionProblem(2, [](double, const VectorXd& y, VectorXd& f) {
        f[0] = y[1];
        f[1] = -kStiff * y[0];
    });
}
double stiff_energy(double x, double v) { return 0.5 * v * v + 0.5 * kStiff * x * x; }

}  // namespace

TEST(StiffSpring, Rk4AtAMillisecondIsDetectedAsUnstable) {
    FunctionProblem problem = stiff_spring();
    mbd::IntegratorSettings s;
    s.step = 1e-3;  // h w = 10, far outside RK4's stability interval (2.8)
    VectorXd y0(2);
    y0 << 1e-3, 0.0;
    try {
        run("rk4", s, problem, 0.0, y0, grid(0.0, 1.0, 100));
        FAIL() << "no DynamicsError";
    } catch (const mbd::DynamicsError& e) {
        std::printf("RK4 stiff spring: %s\n", e.what());
        const std::string what = e.what();
        EXPECT_TRUE(what.find("grew without bound") != std::string::npos ||
                    what.find("non-finite") != std::string::npos)
            << what;
        EXPECT_GT(e.time(), 0.0);
        EXPECT_LT(e.time(), 1.0);
    }
}

TEST(StiffSpring, Dopri5SucceedsOnlyWithManySmallSteps) {
    FunctionProblem problem = stiff_spring();
    mbd::IntegratorSettings s;
    s.tolerance = 1e-6;
    VectorXd y0(2);
    y0 << 1e-3, 0.0;
    const RunResult r = run("dopri5", s, problem, 0.0, y0, grid(0.0, 1.0, 100));
    const VectorXd& y = r.y.back();
    const double e0 = stiff_energy(1e-3, 0.0);
    std::printf("DOPRI5 stiff spring: %ld steps, %ld rejected, %ld rhs; x(1) = %.6e (exact %.6e), E(1)/E0 = %.6f\n",
                r.stats.steps, r.stats.rejected_steps, r.stats.rhs_evaluations, y[0], 1e-3 * std::cos(1e4),
                stiff_energy(y[0], y[1]) / e0);
    // stability bound h w < 3.3: at least w T / 3.3 ~ 3000 steps
    EXPECT_GT(r.stats.steps, 3000);
    EXPECT_NEAR(stiff_energy(y[0], y[1]) / e0, 1.0, 0.05);
}

// ---------------------------------------------------------------- systems for generalized_alpha

namespace {

// A minimal formulation for tests: y = [q; v], f = [qdot; vdot] with vdot from
// the augmented (KKT) system [M J^T; J 0][vdot; lambda] = [Q; gamma], dense.
class TestFormulation : public mbd::Formulation {
public:
    void bind(mbd::System& system, const mbd::FormulationOptions&) override {
        system_ = &system;
        index3_.bind(system);
    }
    int ode_size() const override { return system_->nq() + system_->nv(); }
    void to_ode(const mbd::State& state, VectorXd& y) override {
        y.resize(ode_size());
        y << state.q, state.v;
    }
    void from_ode(double t, const VectorXd& y, mbd::State& state) override {
        state.t = t;
        state.q = y.head(system_->nq());
        state.v = y.tail(system_->nv());
    }
    void rhs(double t, const VectorXd& y, VectorXd& ydot) override {
        mbd::State s;
        from_ode(t, y, s);
        VectorXd vdot, lambda;
        solve(s, vdot, lambda);
        ydot.resize(ode_size());
        ydot << system_->coordinate_rates(s.q, s.v), vdot;
    }
    void multipliers(const mbd::State& state, VectorXd& lambda) override {
        VectorXd vdot;
        solve(state, vdot, lambda);
    }
    void accelerations(const mbd::State& state, VectorXd& vdot) override {
        VectorXd lambda;
        solve(state, vdot, lambda);
    }
    mbd::Index3Problem* index3_problem() override { return &index3_; }

private:
    void solve(const mbd::State& s, VectorXd& vdot, VectorXd& lambda) const {
        const int nv = system_->nv();
        mbd::ConstraintValues cv;
        system_->constraints(s, cv, true);
        const int nc = static_cast<int>(cv.C.size());
        VectorXd Q;
        system_->generalized_forces(s, Q);
        Eigen::MatrixXd A = Eigen::MatrixXd::Zero(nv + nc, nv + nc);
        A.topLeftCorner(nv, nv) = Eigen::MatrixXd(system_->mass_matrix());
        const Eigen::MatrixXd J(cv.J);
        A.block(nv, 0, nc, nv) = J;
        A.block(0, nv, nv, nc) = J.transpose();
        VectorXd b(nv + nc);
        b << Q, cv.gamma;
        const VectorXd x = A.fullPivLu().solve(b);
        vdot = x.head(nv);
        lambda = x.tail(nc);
    }
    mbd::System* system_ = nullptr;
    mbd::SystemIndex3Problem index3_{*this};
};

struct Loaded {
    mbd::Model model;
    std::unique_ptr<mbd::ModelSystem> system;
    TestFormulation formulation;
    mbd::State state;
};

std::unique_ptr<Loaded> load(const std::string& relative) {
    auto l = std::make_unique<Loaded>();
    l->model = mbd::load_scene(mbd::test::scene_path(relative), mbd::test::shared_registry());
    l->system = std::make_unique<mbd::ModelSystem>(l->model);
    l->formulation.bind(*l->system, {});
    l->state = l->system->initial_state();
    l->system->assemble(l->state);
    l->system->consistent_velocities(l->state);
    return l;
}

}  // namespace

TEST(GeneralizedAlpha, RefusesProblemsWithoutAnIndex3Formulation) {
    FunctionProblem problem = stiff_spring();
    mbd::IntegratorSettings s;
    s.step = 1e-3;
    VectorXd y0(2);
    y0 << 1e-3, 0.0;
    try {
        run("generalized_alpha", s, problem, 0.0, y0, {1.0});
        FAIL() << "no InputError";
    } catch (const mbd::InputError& e) {
        EXPECT_NE(std::string(e.what()).find("generalized_alpha needs the formulation's index-3 problem"),
                  std::string::npos)
            << e.what();
    }
}

// scenes/dynamics/stiff-spring.yaml: 1 kg block on a prismatic guide along x,
// spring k = 1e8 to the ground, rest length 1, released at x = 1.001.
TEST(StiffSpring, GeneralizedAlphaIsStableAtAMillisecond) {
    auto l = load("dynamics/stiff-spring.yaml");
    ASSERT_EQ(l->system->nv(), 3);
    mbd::FormulationProblem problem(l->formulation, *l->system);
    VectorXd y0;
    l->formulation.to_ode(l->state, y0);
    const double k = 1e8;
    auto energy = [&](const VectorXd& y) {
        const double x = y[0], vx = y[3];
        return 0.5 * vx * vx + 0.5 * k * (x - 1.0) * (x - 1.0);
    };
    const double e0 = energy(y0);
    EXPECT_NEAR(e0, 50.0, 1e-6);
    for (double rho : {1.0, 0.8, 0.5}) {
        mbd::IntegratorSettings s;
        s.step = 1e-3;
        s.rho_infinity = rho;
        const RunResult r = run("generalized_alpha", s, problem, 0.0, y0, grid(0.0, 1.0, 100));
        ASSERT_EQ(r.y.size(), 100u);
        double e_max = 0.0;
        for (const VectorXd& y : r.y) {
            ASSERT_TRUE(y.allFinite());
            e_max = std::max(e_max, energy(y));
            EXPECT_NEAR(y[1], 0.0, 1e-9);  // the guide holds
            EXPECT_NEAR(y[2], 0.0, 1e-9);
        }
        const double e_end = energy(r.y.back());
        std::printf("generalized_alpha stiff spring rho_inf %.1f: %ld steps, %ld newton, max E/E0 %.6f, E(1)/E0 %.3e\n",
                    rho, r.stats.steps, r.stats.newton_iterations, e_max / e0, e_end / e0);
        EXPECT_LE(e_max, e0 * (1.0 + 1e-6));  // energy never grows
        if (rho < 1.0) EXPECT_LT(e_end, 1e-3 * e0);  // the unresolved 1e4 rad/s mode is damped out
        else EXPECT_NEAR(e_end / e0, 1.0, 1e-6);      // rho_inf = 1: no numerical dissipation
    }
}

TEST(StiffSpring, Rk4ThroughTheSceneIsAlsoStopped) {
    auto l = load("dynamics/stiff-spring.yaml");
    mbd::FormulationProblem problem(l->formulation, *l->system);
    VectorXd y0;
    l->formulation.to_ode(l->state, y0);
    mbd::IntegratorSettings s;
    s.step = 1e-3;
    EXPECT_THROW(run("rk4", s, problem, 0.0, y0, grid(0.0, 1.0, 100)), mbd::DynamicsError);
}

// The same scene through the engine's own path: mbd::simulate with the augmented
// formulation plugin (the other side of the integrator interface).
TEST(StiffSpring, ThroughSimulateWithTheAugmentedFormulation) {
    const mbd::Model model =
        mbd::load_scene(mbd::test::scene_path("dynamics/stiff-spring.yaml"), mbd::test::shared_registry());
    const double e0 = 50.0;  // 0.5 k (1e-3)^2
    {
        mbd::SimulationSettings s;
        s.formulation = "augmented";
        s.integrator = "generalized_alpha";
        s.integration.step = 1e-3;
        s.integration.rho_infinity = 0.8;
        s.t_end = 1.0;
        s.output_step = 0.01;
        s.progress = false;
        double e_max = 0.0, e_end = 0.0;
        const mbd::SimulationResult r = mbd::simulate(model, mbd::test::shared_registry(), s,
                                                      [&](const mbd::SimulationSample& sample) {
                                                          const double x = sample.state.q[0], v = sample.state.v[0];
                                                          e_end = 0.5 * v * v + 0.5 * 1e8 * (x - 1) * (x - 1);
                                                          e_max = std::max(e_max, e_end);
                                                          return true;
                                                      });
        std::printf("simulate augmented + generalized_alpha: %ld steps, %ld newton, max E/E0 %.6f, E(1)/E0 %.3e, "
                    "final |C| %.2e\n",
                    r.stats.steps, r.stats.newton_iterations, e_max / e0, e_end / e0, r.final_position_violation);
        EXPECT_EQ(r.stats.steps, 1000);
        EXPECT_LE(e_max, e0 * (1 + 1e-6));
        EXPECT_LT(e_end, 1e-3 * e0);
    }
    {
        mbd::SimulationSettings s;
        s.formulation = "augmented";
        s.integrator = "rk4";
        s.integration.step = 1e-3;
        s.t_end = 1.0;
        s.progress = false;
        try {
            mbd::simulate(model, mbd::test::shared_registry(), s);
            FAIL() << "no DynamicsError";
        } catch (const mbd::DynamicsError& e) {
            std::printf("simulate augmented + rk4: %s\n", e.what());
            EXPECT_LT(e.time(), 1.0);
        }
    }
}

// scenes/examples/planar-revolute.yaml: a 1 m slender link (m = 1, J = 1/12) pinned
// at the origin, released at rest 30 degrees from the vertical. 1-DOF equation:
// J_O phi'' = -m g c sin(phi), J_O = 1/3, c = 1/2, phi = theta_body + pi/2.
TEST(GeneralizedAlpha, PendulumConvergesAtSecondOrderAndHoldsTheConstraint) {
    auto l = load("examples/planar-revolute.yaml");
    ASSERT_EQ(l->system->nv(), 3);
    ASSERT_EQ(l->system->constraint_rows(), 2);
    mbd::FormulationProblem problem(l->formulation, *l->system);
    VectorXd y0;
    l->formulation.to_ode(l->state, y0);
    const double pi = std::acos(-1.0);
    const double phi0 = y0[2] + pi / 2;
    ASSERT_NEAR(phi0, pi / 6, 1e-12);

    // reference: the 1-DOF equation, DOPRI5 at tol 1e-13
    const double w2 = 1.0 * 9.81 * 0.5 / (1.0 / 3.0);
    FunctionProblem one_dof(2, [&](double, const VectorXd& y, VectorXd& f) {
        f[0] = y[1];
        f[1] = -w2 * std::sin(y[0]);
    });
    const double T = 1.0;
    const std::vector<double> outputs = grid(0.0, T, 20);
    mbd::IntegratorSettings ref_settings;
    ref_settings.tolerance = 1e-13;
    VectorXd z0(2);
    z0 << phi0, 0.0;
    const RunResult ref = run("dopri5", ref_settings, one_dof, 0.0, z0, outputs);

    std::vector<double> errors;
    for (double h : {0.01, 0.005, 0.0025}) {
        mbd::IntegratorSettings s;
        s.step = h;
        s.rho_infinity = 0.8;
        const RunResult r = run("generalized_alpha", s, problem, 0.0, y0, outputs);
        ASSERT_EQ(r.y.size(), outputs.size());
        double err = 0.0, c_max = 0.0;
        for (size_t k = 0; k < outputs.size(); ++k) {
            const VectorXd& y = r.y[k];
            err = std::max(err, std::abs(y[2] + pi / 2 - ref.y[k][0]));
            // the joint itself, written here: the point (0, 0) on the link at -0.5 along its x axis
            const double cx = y[0] - 0.5 * std::cos(y[2]), cy = y[1] - 0.5 * std::sin(y[2]);
            c_max = std::max({c_max, std::abs(cx), std::abs(cy)});
            mbd::State st;
            l->formulation.from_ode(outputs[k], y, st);
            mbd::ConstraintValues cv;
            l->system->constraints(st, cv);
            EXPECT_LT(cv.C.lpNorm<Eigen::Infinity>(), 1e-9);
        }
        std::printf("generalized_alpha pendulum h = %.4f: max angle error %.3e, max |C| %.2e, %ld steps, %ld newton, "
                    "%ld jacobians\n",
                    h, err, c_max, r.stats.steps, r.stats.newton_iterations, r.stats.jacobian_evaluations);
        EXPECT_LT(c_max, 1e-9);  // Newton tolerance 1e-3 * settings.tolerance
        errors.push_back(err);
    }
    mbd::test::expect_order_under_halving(errors, 1.7, 2.3, "generalized_alpha pendulum");
}

// The Newton iteration converges in the velocities too, with the iteration matrix kept across
// steps. scenes/extreme/whirling-pendulum.yaml: a 1 m, 1 kg rod pinned at one end, launched at
// 60 rad/s, whose angle grows without bound. The oracle is the same run with the Newton
// tolerance at round-off (tolerance 1e-16): both solve the same step equations, so at the case's
// tolerance 1e-10 (Newton 1e-13) the energy E = m |v|^2 / 2 + J w^2 / 2 + m g y and the angular
// velocity must follow the tight run's to 1e-9 of their size.
TEST(GeneralizedAlpha, KeptIterationMatrixConvergesInTheVelocities) {
    const mbd::Model model =
        mbd::load_scene(mbd::test::scene_path("extreme/whirling-pendulum.yaml"), mbd::test::shared_registry());
    struct Run {
        double drift = 0.0, energy = 0.0, omega = 0.0, scale = 0.0;
        long newton = 0, jacobians = 0;
    };
    auto run_at = [&](double tolerance) {
        mbd::SimulationSettings s;
        s.formulation = "augmented";
        s.integrator = "generalized_alpha";
        s.integration.step = 1e-4;
        s.integration.tolerance = tolerance;
        s.integration.rho_infinity = 0.8;
        s.t_end = 2.0;
        s.output_step = 0.05;
        s.progress = false;
        Run out;
        double e0 = 0.0;
        bool first = true;
        const mbd::SimulationResult r =
            mbd::simulate(model, mbd::test::shared_registry(), s, [&](const mbd::SimulationSample& sample) {
                const VectorXd& v = sample.state.v;
                const double kinetic = 0.5 * (v[0] * v[0] + v[1] * v[1]) + 0.5 / 12.0 * v[2] * v[2];
                const double e = kinetic + 9.81 * sample.state.q[1];
                if (first) e0 = e, out.scale = kinetic, first = false;
                out.drift = std::max(out.drift, std::abs(e - e0));
                out.omega = v[2];
                out.energy = e;
                return true;
            });
        out.newton = r.stats.newton_iterations;
        out.jacobians = r.stats.jacobian_evaluations;
        return out;
    };
    const Run tight = run_at(1e-16), run = run_at(1e-10);
    std::printf("generalized_alpha whirling pendulum, 2 s: tolerance 1e-10: drift / T0 %.2e, %ld newton, %ld jacobians; "
                "1e-16: drift / T0 %.2e, %ld newton, %ld jacobians; final E %.15g vs %.15g, w %.15g vs %.15g\n",
                run.drift / run.scale, run.newton, run.jacobians, tight.drift / tight.scale, tight.newton,
                tight.jacobians, run.energy, tight.energy, run.omega, tight.omega);
    EXPECT_NEAR(run.energy, tight.energy, 1e-9 * tight.scale);
    EXPECT_NEAR(run.drift, tight.drift, 1e-9 * tight.scale);
    EXPECT_NEAR(run.omega, tight.omega, 1e-9 * std::abs(tight.omega));
    EXPECT_LT(run.jacobians, run.newton / 2);  // the matrix is kept: fewer factorizations than iterations
}

TEST(GeneralizedAlpha, LargeStepsConvergeOrFailNamingTheJoint) {
    auto l = load("examples/planar-revolute.yaml");
    mbd::FormulationProblem problem(l->formulation, *l->system);
    VectorXd y0;
    l->formulation.to_ode(l->state, y0);
    {
        // h = 0.2 s (8 steps per period): Newton needs the geometric stiffness, added on slow contraction
        mbd::IntegratorSettings s;
        s.step = 0.2;
        const RunResult r = run("generalized_alpha", s, problem, 0.0, y0, grid(0.0, 10.0, 10));
        for (const VectorXd& y : r.y) {
            const double cx = y[0] - 0.5 * std::cos(y[2]), cy = y[1] - 0.5 * std::sin(y[2]);
            EXPECT_LT(std::max(std::abs(cx), std::abs(cy)), 1e-9);
        }
        std::printf("generalized_alpha pendulum h = 0.2: %ld steps, %ld newton\n", r.stats.steps,
                    r.stats.newton_iterations);
    }
    {
        // h = 5 s: hopeless; the error names the time and the joint row
        mbd::IntegratorSettings s;
        s.step = 5.0;
        try {
            run("generalized_alpha", s, problem, 0.0, y0, {10.0});
            FAIL() << "no DynamicsError";
        } catch (const mbd::DynamicsError& e) {
            std::printf("generalized_alpha h = 5: %s\n", e.what());
            const std::string what = e.what();
            EXPECT_NE(what.find("Newton iteration did not converge at t = "), std::string::npos) << what;
            EXPECT_NE(what.find("joint 'pivot'"), std::string::npos) << what;
            EXPECT_TRUE(e.time() == 5.0 || e.time() == 10.0) << e.time();
        }
    }
}

// A re-selection of the independent coordinates in project() redefines part of the
// ODE state (embedding: v_i, hamiltonian: p); cvode must restart its BDF history
// there (Formulation::state_redefined, CVodeReInit). Both runs used to fail with a
// step-size collapse (bricard at t = 1.36, the four-bar at t = 0.318).
namespace {
// `keys`: a `formulation:` map for the scene (e.g. the embedding's dense path, the one that re-selects)
std::vector<mbd::SimulationSample> simulate_all(const std::string& scene, const std::string& formulation,
                                                const std::string& integrator, double tolerance, double t_end,
                                                const std::string& keys = "") {
    const mbd::Model model =
        keys.empty() ? mbd::load_scene(mbd::test::scene_path(scene), mbd::test::shared_registry())
                     : mbd::load_scene_text(mbd::test::read_text(mbd::test::scene_path(scene)) + "\nformulation: " + keys +
                                                "\n",
                                            mbd::test::scene_path(scene).string(), mbd::test::shared_registry());
    mbd::SimulationSettings s;
    s.formulation = formulation;
    s.integrator = integrator;
    s.integration.tolerance = tolerance;
    s.t_end = t_end;
    s.output_step = 0.01;
    s.progress = false;
    std::vector<mbd::SimulationSample> samples;
    const mbd::SimulationResult r = mbd::simulate(model, mbd::test::shared_registry(), s,
                                                  [&](const mbd::SimulationSample& sample) {
                                                      samples.push_back(sample);
                                                      return true;
                                                  });
    std::printf("%s %s + %s tol %.0e: %ld steps, %ld rejected, final |C| %.2e\n", scene.c_str(), formulation.c_str(),
                integrator.c_str(), tolerance, r.stats.steps, r.stats.rejected_steps, r.final_position_violation);
    return samples;
}

double max_position_difference(const std::vector<mbd::SimulationSample>& a, const std::vector<mbd::SimulationSample>& b) {
    EXPECT_EQ(a.size(), b.size());
    double d = 0.0;
    for (size_t i = 0; i < std::min(a.size(), b.size()); ++i)
        d = std::max(d, (a[i].state.q - b[i].state.q).lpNorm<Eigen::Infinity>());
    return d;
}
}  // namespace

TEST(Cvode, RestartsAfterAnEmbeddingReselectionOnBricard) {
    const std::string dense = "{type: embedding, path: dense}";  // path: auto takes the closure path, which never re-selects
    const auto cvode = simulate_all("book/bricard.yaml", "embedding", "cvode", 1e-10, 2.0, dense);
    const auto dopri5 = simulate_all("book/bricard.yaml", "embedding", "dopri5", 1e-10, 2.0, dense);
    ASSERT_FALSE(cvode.empty());
    EXPECT_NEAR(cvode.back().state.t, 2.0, 1e-12);
    const double d = max_position_difference(cvode, dopri5);
    std::printf("bricard embedding cvode vs dopri5 (tol 1e-10, 2 s): max |dq| %.3e\n", d);
    EXPECT_LT(d, 1e-6);
}

TEST(Cvode, RestartsAfterAHamiltonianReselectionOnTheFourBar) {
    const auto cvode = simulate_all("dynamics/four-bar-conservative.yaml", "hamiltonian", "cvode", 1e-10, 1.0);
    const auto dopri5 = simulate_all("dynamics/four-bar-conservative.yaml", "hamiltonian", "dopri5", 1e-10, 1.0);
    ASSERT_FALSE(cvode.empty());
    EXPECT_NEAR(cvode.back().state.t, 1.0, 1e-12);
    const double d = max_position_difference(cvode, dopri5);
    std::printf("four-bar hamiltonian cvode vs dopri5 (tol 1e-10, 1 s): max |dq| %.3e\n", d);
    EXPECT_LT(d, 1e-5);  // measured 3.5e-6 (cvode's global error at this tolerance)
}
