// A trial stage of an adaptive step that lands where the motion is not finite (a body driven
// through a contact plane by too long a step, a state the forces cannot be evaluated at) only says
// the step was too long: the adaptive integrators reject it and retry shorter
// (kit formulation.hpp NonFiniteMotion); any other DynamicsError still stops the run.
#include "support/function_problem.hpp"

#include <mbd/integrator.hpp>
#include <mbd/kit/non_finite_motion.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace {

using Eigen::VectorXd;
using mbd::test::FunctionProblem;
using mbd::test::run;

// y' = -k (y - 1), y(0) = 0: y = 1 - exp(-k t) stays in [0, 1). The right-hand side cannot be
// evaluated outside [-1, 2] (as a contact law beyond its reach): an explicit stage of a step much
// longer than 1/k overshoots there.
constexpr double kRate = 1e3;
FunctionProblem bounded_relaxation(long* refused) {
    return FunctionProblem(1, [refused](double t, const VectorXd& y, VectorXd& f) {
        if (y[0] > 2.0 || y[0] < -1.0) {
            ++*refused;
            throw mbd::NonFiniteMotion(t, "non-finite generalized forces: the motion diverged (test)");
        }
        f[0] = -kRate * (y[0] - 1.0);
    });
}

class NonFiniteTrial : public ::testing::TestWithParam<std::string> {};

TEST_P(NonFiniteTrial, IsARejectedStepNotTheEndOfTheRun) {
    long refused = 0;
    FunctionProblem problem = bounded_relaxation(&refused);
    mbd::IntegratorSettings settings;
    settings.tolerance = 1e-8;
    settings.step = 0.5;  // the first step: 500 time constants, its stages far outside [-1, 2]
    VectorXd y0(1);
    y0 << 0.0;
    const auto r = run(GetParam(), settings, problem, 0.0, y0, {0.002, 0.01});
    EXPECT_GT(refused, 0) << "the test did not reach a non-finite trial state";
    ASSERT_EQ(r.y.size(), 2u);
    EXPECT_NEAR(r.y[0][0], 1.0 - std::exp(-kRate * 0.002), 1e-6);
    EXPECT_NEAR(r.y[1][0], 1.0 - std::exp(-kRate * 0.01), 1e-6);
}

INSTANTIATE_TEST_SUITE_P(AdaptiveIntegrators, NonFiniteTrial, ::testing::Values("dopri5", "dop853", "cvode"));

// At an accepted state (the output, a fixed-step method) the same error stops the run.
TEST(NonFiniteState, StopsAFixedStepRun) {
    long refused = 0;
    FunctionProblem problem = bounded_relaxation(&refused);
    mbd::IntegratorSettings settings;
    settings.step = 0.5;
    VectorXd y0(1);
    y0 << 0.0;
    EXPECT_THROW(run("rk4", settings, problem, 0.0, y0, {1.0}), mbd::NonFiniteMotion);
    EXPECT_GT(refused, 0);
}

}  // namespace
