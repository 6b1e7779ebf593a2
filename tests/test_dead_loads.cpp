// Dead loads in statics: a constant point force in world axes is conservative (potential
// -F . r_P, plugins/forces/point_force), so `mbd statics` minimises the potential energy.
// Oracle: a double pendulum (uniform links hinged end to end, hanging under gravity) with a
// horizontal force F at the mass centre of the second link. The second link carries only its
// weight and F through its centre, so it lines up with their resultant: its angle from the
// downward vertical is atan(F / (m2 g)). The first link carries F and m2 g at its tip and its own
// weight at its middle: moments about the ground pin give tan(phi1) = F / ((m1 / 2 + m2) g). The
// pins carry, on the link below them, (-F, (m1 + m2) g) and (-F, m2 g).
#include "support/test_support.hpp"

#include <mbd/statics_analysis.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace mbd {
namespace {

constexpr double kG = 9.81, kM1 = 2.0, kM2 = 1.5, kL1 = 1.0, kL2 = 0.8, kF = 7.0;

// The links hang straight down at the start; `spatial`: the same in the x-z plane, hinged about y.
std::string double_pendulum(bool spatial) {
    using test::g17;
    if (!spatial)
        return "dimension: planar\ngravity: [0, " + g17(-kG) + "]\nbodies:\n"
               "  - {name: upper, mass: " + g17(kM1) + ", inertia: 0.2, position: [0, " + g17(-kL1 / 2) + "]}\n"
               "  - {name: lower, mass: " + g17(kM2) + ", inertia: 0.1, position: [0, " + g17(-kL1 - kL2 / 2) + "]}\n"
               "joints:\n"
               "  - {name: shoulder, type: revolute, bodies: [ground, upper], point: [0, 0]}\n"
               "  - {name: elbow, type: revolute, bodies: [upper, lower], point: [0, " + g17(-kL1) + "]}\n"
               "forces:\n  - {name: push, type: point_force, body: lower, force: [" + g17(kF) + ", 0]}\n";
    return "dimension: spatial\ngravity: [0, 0, " + g17(-kG) + "]\nbodies:\n"
           "  - {name: upper, mass: " + g17(kM1) + ", inertia: [0.2, 0.2, 0.01], position: [0, 0, " + g17(-kL1 / 2) + "]}\n"
           "  - {name: lower, mass: " + g17(kM2) + ", inertia: [0.1, 0.1, 0.01], position: [0, 0, " +
           g17(-kL1 - kL2 / 2) + "]}\n"
           "joints:\n"
           "  - {name: shoulder, type: revolute, bodies: [ground, upper], point: [0, 0, 0], axis: [0, 1, 0]}\n"
           "  - {name: elbow, type: revolute, bodies: [upper, lower], point: [0, 0, " + g17(-kL1) + "], axis: [0, 1, 0]}\n"
           "forces:\n  - {name: push, type: point_force, body: lower, force: [" + g17(kF) + ", 0, 0]}\n";
}

TEST(DeadLoads, ADoublePendulumPushedSidewaysRestsAtTheClosedFormAngles) {
    const double phi1 = std::atan(kF / ((kM1 / 2 + kM2) * kG)), phi2 = std::atan(kF / (kM2 * kG));
    for (const bool spatial : {false, true}) {
        const Model model = test::scene(double_pendulum(spatial));
        const StaticsReport report = run_statics(model, test::shared_registry(), StaticsOptions{});
        const StaticsResult& r = report.result;
        ASSERT_TRUE(r.converged) << r.status << ": " << r.message;
        EXPECT_EQ(r.objective, "potential");  // gravity and the dead load
        EXPECT_EQ(r.stability, "stable");
        // the mass centres, world x and the vertical (planar y, spatial z)
        const int stride = spatial ? 7 : 3, up = spatial ? 2 : 1;
        const double x1 = kL1 / 2 * std::sin(phi1), v1 = -kL1 / 2 * std::cos(phi1);
        const double x2 = kL1 * std::sin(phi1) + kL2 / 2 * std::sin(phi2);
        const double v2 = -kL1 * std::cos(phi1) - kL2 / 2 * std::cos(phi2);
        std::printf("%s: lower link at (%.12f, %.12f), closed form (%.12f, %.12f)\n", spatial ? "spatial" : "planar",
                    r.state.q[stride], r.state.q[stride + up], x2, v2);
        EXPECT_NEAR(r.state.q[0], x1, 1e-9);
        EXPECT_NEAR(r.state.q[up], v1, 1e-9);
        EXPECT_NEAR(r.state.q[stride], x2, 1e-9);
        EXPECT_NEAR(r.state.q[stride + up], v2, 1e-9);
        if (!spatial) {
            EXPECT_NEAR(r.state.q[2], phi1, 1e-9);  // the body angles
            EXPECT_NEAR(r.state.q[5], phi2, 1e-9);
        }
        // the pins' reactions on the link below them
        ASSERT_EQ(report.reactions.size(), 2u);
        EXPECT_NEAR(report.reactions[0].force.x(), -kF, 1e-8);
        EXPECT_NEAR(report.reactions[0].force[up], (kM1 + kM2) * kG, 1e-8);
        EXPECT_NEAR(report.reactions[1].force.x(), -kF, 1e-8);
        EXPECT_NEAR(report.reactions[1].force[up], kM2 * kG, 1e-8);
    }
}

}  // namespace
}  // namespace mbd
