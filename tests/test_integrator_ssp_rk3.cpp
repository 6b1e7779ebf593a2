// SSP-RK3 (core/src/integrators/ssp_rk3.cpp, Shu and Osher 1988) against closed forms:
//   one step of y' = lambda y multiplies y by the cubic Taylor polynomial of e^z, z = h lambda
//     (every third-order three-stage Runge-Kutta does; a wrong weight changes it);
//   the harmonic oscillator x'' = -w^2 x, x = cos wt: the error at T falls as h^3;
//   the strong stability it is named for: on y' = -y with the largest step forward Euler keeps
//     monotone (h = 1), the solution never grows and never turns negative.
#include "support/convergence_order.hpp"
#include "support/function_problem.hpp"

#include <mbd/integrator.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

namespace {

using Eigen::VectorXd;
using mbd::test::FunctionProblem;
using mbd::test::run;

FunctionProblem linear(double lambda) {
    return FunctionProblem(1, [lambda](double, const VectorXd& y, VectorXd& f) { f[0] = lambda * y[0]; });
}

}  // namespace

TEST(SspRk3, OneStepIsTheCubicTaylorPolynomialOfTheExponential) {
    const double lambda = -3.0, h = 0.1, z = h * lambda;
    FunctionProblem problem = linear(lambda);
    mbd::IntegratorSettings s;
    s.step = h;
    const auto r = run("ssp_rk3", s, problem, 0.0, VectorXd::Ones(1), {h});
    EXPECT_NEAR(r.y.back()[0], 1.0 + z + z * z / 2.0 + z * z * z / 6.0, 1e-15);
    EXPECT_EQ(r.stats.steps, 1);
    EXPECT_EQ(r.stats.rhs_evaluations, 3);
}

TEST(SspRk3, ThirdOrderOnTheHarmonicOscillator) {
    std::vector<double> errors;
    for (double h : {0.04, 0.02, 0.01, 0.005}) errors.push_back(mbd::test::oscillator_error("ssp_rk3", h));
    mbd::test::expect_order_under_halving(errors, 2.8, 3.2, "SSP-RK3 oscillator");
}

TEST(SspRk3, KeepsForwardEulersMonotoneDecayAtItsLargestStep) {
    // forward Euler on y' = -y is monotone for h <= 1 (y_{n+1} = (1 - h) y_n); SSP-RK3's
    // coefficient is 1, so at h = 1 each step multiplies by 1 - 1 + 1/2 - 1/6 = 1/3
    FunctionProblem problem = linear(-1.0);
    mbd::IntegratorSettings s;
    s.step = 1.0;
    const auto r = run("ssp_rk3", s, problem, 0.0, VectorXd::Ones(1), {1.0, 2.0, 3.0, 4.0, 5.0});
    double previous = 1.0;
    for (const VectorXd& y : r.y) {
        EXPECT_NEAR(y[0], previous / 3.0, 1e-15);
        EXPECT_GE(y[0], 0.0);
        previous = y[0];
    }
}
