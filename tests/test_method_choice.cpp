// The automatic choice of formulation and integrator (core method_choice.hpp,
// docs/user-guide.md "The automatic choice"): the topology rule, the damping-rate estimate
// against closed forms, the stiffness rule on the flyball, and what a run reports.
#include <mbd/method_choice.hpp>
#include <mbd/simulation.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "support/test_support.hpp"

namespace {

using mbd::test::g17;

// Two planar bodies (masses m1, m2; m2 may be the ground) joined by a spring-damper between
// their mass centres along x, no joints: the one damped mode has the rate c (1/m1 + 1/m2).
std::string damper_scene(double m1, double m2, double c, bool to_ground) {
    std::string s = "dimension: planar\ngravity: [0, 0]\nbodies:\n  - {name: a, mass: " + g17(m1) +
                    ", inertia: 0.01, position: [0, 0]}\n";
    if (!to_ground) s += "  - {name: b, mass: " + g17(m2) + ", inertia: 0.02, position: [1, 0]}\n";
    s += "forces:\n  - {name: d, type: spring_damper, bodies: [a, " + std::string(to_ground ? "ground" : "b") +
         "], points: [[0, 0], [" + std::string(to_ground ? "1" : "0") + ", 0]], stiffness: 100, damping: " + g17(c) +
         ", rest_length: 1}\n";
    return s;
}

TEST(MethodChoice, TheFastestDampingRateIsThatOfTheDampedMode) {
    // to the ground: c / m
    EXPECT_NEAR(mbd::fastest_damping_rate(mbd::test::scene(damper_scene(2.0, 0.0, 30.0, true))), 15.0, 1e-9);
    // between two free bodies: c (1/m1 + 1/m2), the reduced mass
    EXPECT_NEAR(mbd::fastest_damping_rate(mbd::test::scene(damper_scene(2.0, 3.0, 30.0, false))),
                30.0 * (1.0 / 2.0 + 1.0 / 3.0), 1e-9);
    // no damper: no rate
    EXPECT_EQ(mbd::fastest_damping_rate(mbd::test::scene(damper_scene(2.0, 3.0, 0.0, false))), 0.0);
}

TEST(MethodChoice, TreesTakeTheRecursiveEmbeddingAndLoopsAugmented) {
    const mbd::MethodChoice pendulum =
        mbd::automatic_method(mbd::test::load("dynamics/pendulum-a01.yaml"), 10.0);
    EXPECT_EQ(pendulum.formulation, "embedding");
    EXPECT_EQ(pendulum.integrator, "dop853");
    EXPECT_NE(pendulum.formulation_reason.find("tree"), std::string::npos) << pendulum.formulation_reason;
    const mbd::MethodChoice four_bar =
        mbd::automatic_method(mbd::test::load("dynamics/four-bar-conservative.yaml"), 10.0);
    EXPECT_EQ(four_bar.formulation, "augmented");
    EXPECT_NE(four_bar.formulation_reason.find("closed loop"), std::string::npos) << four_bar.formulation_reason;
    // a driven tree: the recursive path prescribes the driven joint's motion
    const mbd::MethodChoice driven = mbd::automatic_method(
        mbd::test::scene("dimension: planar\ngravity: [0, -9.81]\nbodies:\n"
                         "  - {name: rod, mass: 1, inertia: 0.1, position: [0.5, 0], angle: 0}\n"
                         "joints:\n  - {name: pin, type: revolute, bodies: [ground, rod], point: [0, 0]}\n"
                         "drivers:\n  - {name: swing, joint: pin, motion: {type: linear, initial: 0, rate: 1}}\n"),
        1.0);
    EXPECT_EQ(driven.formulation, "embedding");
    EXPECT_NE(driven.formulation_reason.find("driven (prescribed motion)"), std::string::npos)
        << driven.formulation_reason;
}

TEST(MethodChoice, TheFlyballIsStiffAndTakesCvode) {
    // two spring-dampers of c = 4e4 N s/m between 5.3 kg arms and a 3 kg slider
    const mbd::Model flyball = mbd::test::load("bench/a05-flyball.yaml");
    const double rate = mbd::fastest_damping_rate(flyball);
    EXPECT_GT(rate, 4e4 / 3.0);  // at least the slider's own c / m
    const mbd::MethodChoice choice = mbd::automatic_method(flyball, 2.0);
    EXPECT_EQ(choice.integrator, "cvode");
    EXPECT_NE(choice.integrator_reason.find("stiff"), std::string::npos) << choice.integrator_reason;
    // a driven tree: the recursive path's joint coordinates with the motor prescribed (6 states,
    // not 52) for cvode
    EXPECT_EQ(choice.formulation, "embedding");
    EXPECT_NE(choice.formulation_reason.find("recursive path"), std::string::npos) << choice.formulation_reason;
    // the same scene over a time short against 1e4 damped time scales is not stiff: the same
    // formulation with the explicit pair
    const mbd::MethodChoice brief = mbd::automatic_method(flyball, 0.5 * mbd::kStiffDampedTimeScales / rate);
    EXPECT_EQ(brief.integrator, "dop853");
    EXPECT_EQ(brief.formulation, "embedding");
}

TEST(MethodChoice, ARunWithoutChoicesReportsTheAutomaticOnesAndTheIndexThreeIntegratorTakesAugmented) {
    const mbd::Model pendulum = mbd::test::load("dynamics/pendulum-a01.yaml");
    std::vector<std::string> messages;
    mbd::SimulationSettings s;
    s.t_end = 0.2;
    s.progress = false;
    s.messages = mbd::MessageLog([&](const std::string& line) { messages.push_back(line); });
    const mbd::SimulationResult r = mbd::simulate(pendulum, mbd::test::shared_registry(), s);
    EXPECT_EQ(r.formulation, "embedding");
    EXPECT_EQ(r.integrator, "dop853");
    ASSERT_GE(messages.size(), 2u);
    EXPECT_NE(messages[0].find("formulation embedding (automatic: tree"), std::string::npos) << messages[0];
    EXPECT_NE(messages[1].find("integrator dop853 (automatic: not stiff"), std::string::npos) << messages[1];
    // generalized_alpha needs the index-3 form: the automatic formulation is augmented
    s.integrator = "generalized_alpha";
    s.integration.step = 1e-3;
    messages.clear();
    EXPECT_EQ(mbd::simulate(pendulum, mbd::test::shared_registry(), s).formulation, "augmented");
    EXPECT_NE(messages[0].find("generalized_alpha needs its index-3 form"), std::string::npos) << messages[0];
}

}  // namespace
