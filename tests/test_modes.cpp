// Linearisation and modes (issue 17) against closed forms: a compound pendulum's
// small-oscillation frequency sqrt(m g l / I), a fixed-fixed chain of three equal masses
// and four equal springs (omega^2 = (k/m)(2 - sqrt 2), 2k/m, (k/m)(2 + sqrt 2)), a damped
// spring-mass's damping ratio c / (2 sqrt(k m)); the input matrix of an actuated pendulum
// (1/I); the refusal of a state that is not an equilibrium.
#include "support/test_support.hpp"

#include <mbd/linearisation.hpp>
#include <mbd/modes.hpp>
#include <mbd/model_system.hpp>
#include <mbd/sdk/text.hpp>
#include <mbd/statics_analysis.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace {

using mbd::test::g17;
using mbd::test::scene;

mbd::ModeAnalysis modes_of_scene(const mbd::Model& model, mbd::LinearModel* linear_out = nullptr) {
    mbd::ModelSystem system(model);
    const mbd::LinearModel linear = mbd::linearise(system, model.initial_state(), mbd::scene_actuators(model));
    if (linear_out) *linear_out = linear;
    return mbd::modes_of(linear);
}

struct Pendulum {
    double m = 1.7, J = 0.23, l = 0.8, g = 9.81;
    double I() const { return J + m * l * l; }
    // hanging at rest below the pivot, at angle `angle` from the downward vertical
    std::string yaml(double angle = 0.0, bool actuated = false) const {
        std::ostringstream s;
        s << "dimension: planar\ngravity: [0, " << -g << "]\nbodies:\n"
          << "  - {name: link, mass: " << m << ", inertia: " << J << ", position: [" << g17(l * std::sin(angle))
          << ", " << g17(-l * std::cos(angle)) << "], angle: " << g17(angle) << "}\n"
          << "joints:\n  - {name: pivot, type: revolute, bodies: [ground, link], point: [0, 0]}\n";
        if (actuated) s << "actuators:\n  - {name: motor, joint: pivot}\n";
        return s.str();
    }
};

TEST(Modes, PendulumSmallOscillationFrequency) {
    const Pendulum p;
    mbd::LinearModel linear;
    const mbd::ModeAnalysis a = modes_of_scene(scene(p.yaml()), &linear);
    ASSERT_EQ(linear.coordinates.size(), 1u);
    ASSERT_EQ(a.modes.size(), 1u);
    EXPECT_TRUE(a.modes[0].oscillatory);
    const double omega = std::sqrt(p.m * p.g * p.l / p.I());
    EXPECT_NEAR(a.modes[0].natural_frequency, omega, 1e-10 * omega);
    EXPECT_NEAR(a.modes[0].damping_ratio, 0.0, 1e-10);
    EXPECT_TRUE(a.ignorable.empty());
    // its shape in the joint coordinate: the pivot angle moves one to one with the link's angle
    ASSERT_EQ(a.modes[0].joint_shape.size(), 1);
    EXPECT_NEAR(std::abs(a.modes[0].joint_shape[0]), 1.0, 1e-12);
}

TEST(Modes, ActuatedPendulumInputMatrix) {
    const Pendulum p;
    mbd::LinearModel linear;
    modes_of_scene(scene(p.yaml(0.0, true)), &linear);
    ASSERT_EQ(linear.B.rows(), 2);
    ASSERT_EQ(linear.B.cols(), 1);
    EXPECT_NEAR(linear.B(0, 0), 0.0, 1e-14);
    EXPECT_NEAR(linear.B(1, 0), 1.0 / p.I(), 1e-12 / p.I());  // thetaddot = u / I
    EXPECT_EQ(linear.inputs, std::vector<std::string>{"motor"});
}

TEST(Modes, NotAnEquilibriumGivesTheResidual) {
    const Pendulum p;
    const mbd::Model model = scene(p.yaml(0.5));
    mbd::ModelSystem system(model);
    try {
        mbd::linearise(system, model.initial_state(), {});
        FAIL() << "linearised about a state that is not an equilibrium";
    } catch (const mbd::LinearisationError& e) {
        const std::string what = e.what();
        // thetaddot = -m g l sin(0.5) / I
        const double residual = p.m * p.g * p.l * std::sin(0.5) / p.I();
        EXPECT_NE(what.find("not an equilibrium"), std::string::npos) << what;
        EXPECT_NE(what.find(mbd::format_number(residual)), std::string::npos) << what;
    }
}

// Three blocks on x guides at x = 1, 2, 3 joined by springs to each other and to anchors
// at x = 0 and x = 4 (unstretched, no gravity).
std::string chain_yaml(double m, double k, double c) {
    std::ostringstream s;
    s << "dimension: planar\ngravity: [0, 0]\nbodies:\n";
    for (int i = 1; i <= 3; ++i)
        s << "  - {name: b" << i << ", mass: " << m << ", inertia: 0.01, position: [" << i << ", 0]}\n";
    s << "joints:\n";
    for (int i = 1; i <= 3; ++i)
        s << "  - {name: guide" << i << ", type: prismatic, bodies: [ground, b" << i << "], point: [" << i
          << ", 0], axis: [1, 0]}\n";
    s << "forces:\n";
    const char* names[] = {"ground", "b1", "b2", "b3", "ground"};
    for (int i = 0; i < 4; ++i) {
        s << "  - {name: s" << i << ", type: spring_damper, bodies: [" << names[i] << ", " << names[i + 1]
          << "], points: [[" << (i == 0 ? 0 : 0) << ", 0], [" << (i == 3 ? 4 : 0) << ", 0]], stiffness: " << g17(k)
          << ", damping: " << g17(c) << ", rest_length: 1}\n";
    }
    return s.str();
}

TEST(Modes, ThreeMassChainEigenfrequencies) {
    const double m = 2.0, k = 50.0;
    const mbd::ModeAnalysis a = modes_of_scene(scene(chain_yaml(m, k, 0.0)));
    ASSERT_EQ(a.modes.size(), 3u);
    const double expected[] = {std::sqrt(k / m * (2 - std::sqrt(2.0))), std::sqrt(2 * k / m),
                               std::sqrt(k / m * (2 + std::sqrt(2.0)))};
    for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(a.modes[i].natural_frequency, expected[i], 1e-10 * expected[i]) << i;
        EXPECT_NEAR(a.modes[i].damping_ratio, 0.0, 1e-10) << i;
    }
    // the lowest mode: the blocks move in phase, the middle one sqrt 2 times the outer ones
    const Eigen::VectorXcd& s = a.modes[0].joint_shape;
    ASSERT_EQ(s.size(), 3);
    EXPECT_NEAR(std::abs(s[0] / s[1]), 1.0 / std::sqrt(2.0), 1e-10);
    EXPECT_NEAR(std::abs(s[2] / s[1]), 1.0 / std::sqrt(2.0), 1e-10);
}

TEST(Modes, DampedSpringMassDampingRatio) {
    const double m = 1.3, k = 40.0, c = 1.9;
    // one block between the anchor at x = 0 and a spring without stiffness to x = 2
    std::ostringstream s;
    s << "dimension: planar\ngravity: [0, -9.81]\nbodies:\n  - {name: block, mass: " << m
      << ", inertia: 0.01, position: [1, 0]}\njoints:\n"
      << "  - {name: guide, type: prismatic, bodies: [ground, block], point: [1, 0], axis: [1, 0]}\n"
      << "forces:\n  - {name: spring, type: spring_damper, bodies: [ground, block], points: [[0, 0], [0, 0]], "
      << "stiffness: " << k << ", damping: " << c << ", rest_length: 1}\n";
    const mbd::ModeAnalysis a = modes_of_scene(scene(s.str()));
    ASSERT_EQ(a.modes.size(), 1u);
    const double zeta = c / (2 * std::sqrt(k * m)), omega = std::sqrt(k / m);
    EXPECT_NEAR(a.modes[0].damping_ratio, zeta, 1e-10);
    EXPECT_NEAR(a.modes[0].natural_frequency, omega, 1e-10 * omega);
    EXPECT_NEAR(a.modes[0].damped_frequency, omega * std::sqrt(1 - zeta * zeta), 1e-10 * omega);
}

// A block on a frictionless x guide with no force along it: its position is ignorable.
TEST(Modes, FreeCoordinateIsIgnorable) {
    const mbd::Model model = scene(
        "dimension: planar\ngravity: [0, -9.81]\nbodies:\n  - {name: cart, mass: 2, inertia: 0.1, position: [0, 0]}\n"
        "joints:\n  - {name: rail, type: prismatic, bodies: [ground, cart], point: [0, 0], axis: [1, 0]}\n");
    const mbd::ModeAnalysis a = modes_of_scene(model);
    ASSERT_EQ(a.ignorable.size(), 1u);
    // what is left: the free velocity (lambda = 0, a rigid-body mode)
    ASSERT_EQ(a.modes.size(), 1u);
    EXPECT_NEAR(a.modes[0].natural_frequency, 0.0, 1e-12);
}

}  // namespace
