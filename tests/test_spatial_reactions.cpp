// The spatial joint reaction (force and torque, reactions.hpp; book Eqs. 6.146-6.148) against a
// closed form that no formulation computes: a body with products of inertia spinning about a
// fixed vertical hinge under gravity.
//
// The body (mass m, central inertia J-bar with J_xz != 0) hangs on a revolute joint at the
// origin with axis z; its mass centre starts at c = (d, 0, h). Gravity (along -z) has no moment
// about z, so the spin w is constant: theta = w t, A = Rz(theta), R = A c, omega-bar = (0, 0, w).
// Newton:  F = m Rddot - m g = (-m w^2 d cos(theta), -m w^2 d sin(theta), m g_z)  (the joint's
//          force on the body);
// Euler about the mass centre (omega-bar-dot = 0): T_P + (P - R) x F = A (omega-bar x J-bar omega-bar)
//          = A (0, w^2 J_xz, 0), so with P = 0:  T_P = A (0, w^2 J_xz, 0) + R x F,
// whose component along the hinge is zero (an ideal hinge carries no moment about its axis).
#include <mbd/model_system.hpp>
#include <mbd/reactions.hpp>
#include <mbd/simulation.hpp>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>

#include "support/test_support.hpp"

namespace mbd {
namespace {

constexpr double m = 2.0, d = 0.3, h = 0.2, w = 3.0, g = 9.81;
constexpr double J_xz = -0.02;

// The hinge axis may be given in any direction of the marker frame; x_axis turns the marker
// frame about it so that the joint-frame components are checked with a non-trivial frame.
const char* kScene = R"(
dimension: spatial
gravity: [0, 0, -9.81]
bodies:
  - name: arm
    mass: 2
    inertia: [[0.05, 0, -0.02], [0, 0.06, 0], [-0.02, 0, 0.03]]
    position: [0.3, 0, 0.2]
    velocity: [0, 0.9, 0]
    angular_velocity: [0, 0, 3]
joints:
  - {name: hinge, type: revolute, bodies: [ground, arm], point: [0, 0, 0], axis: [0, 0, 1], x_axis: [1, 1, 0]}
)";

TEST(SpatialReactions, SpinningUnbalancedBodyOnAHingeMatchesNewtonEuler) {
    const Model model = test::scene(kScene, "spinning-arm.yaml");
    ModelSystem system(model);
    for (const std::string& formulation : test::shared_registry().type_names("formulation")) {
        SimulationSettings s = test::adaptive_run(formulation, "dopri5", 1e-11, 0.6, 0.1);
        s.reactions = true;
        double worst_force = 0.0, worst_torque = 0.0, worst_joint_frame = 0.0;
        int checked = 0;
        simulate(model, test::shared_registry(), s, [&](const SimulationSample& sample) {
            if (sample.state.t == 0.0) return true;
            EXPECT_TRUE(sample.lambda != nullptr);
            if (!sample.lambda) return false;
            const double theta = w * sample.state.t;
            const Mat3 A = Eigen::AngleAxisd(theta, Vec3::UnitZ()).toRotationMatrix();
            const Vec3 R = A * Vec3(d, 0.0, h);
            const Vec3 F(-m * w * w * d * std::cos(theta), -m * w * w * d * std::sin(theta), m * g);
            const Vec3 T = A * Vec3(0.0, w * w * J_xz, 0.0) + R.cross(F);
            const std::vector<JointReaction> r = joint_reactions(system, sample.state, *sample.lambda);
            EXPECT_EQ(r.size(), 1u);
            EXPECT_EQ(r[0].on.size(), 2u);
            const BodyReaction& on = r[0].on[1];
            EXPECT_EQ(on.body, 0);
            EXPECT_LT(on.point.norm(), 1e-9);  // the hinge point stays at the origin (to the constraint tolerance)
            worst_force = std::max(worst_force, (on.force - F).norm());
            worst_torque = std::max(worst_torque, (on.torque - T).norm());
            // the joint frame on the arm: z along the hinge, x at 45 degrees, turning with the arm
            const Mat3 frame = A * Eigen::AngleAxisd(M_PI / 4, Vec3::UnitZ()).toRotationMatrix();
            worst_joint_frame = std::max({worst_joint_frame, (on.force_joint - frame.transpose() * F).norm(),
                                          (on.torque_joint - frame.transpose() * T).norm()});
            EXPECT_NEAR(on.torque_joint.z(), 0.0, 1e-8) << "an ideal hinge carries no moment about its axis";
            ++checked;
            return true;
        });
        std::printf("%-12s |F - F_exact| %.2e  |T_P - T_exact| %.2e  joint frame %.2e (|F| ~ %.3g, |T| ~ %.3g)\n",
                    formulation.c_str(), worst_force, worst_torque, worst_joint_frame, m * g, m * g * d);
        EXPECT_EQ(checked, 6) << formulation;
        EXPECT_LT(worst_force, 1e-7) << formulation;
        EXPECT_LT(worst_torque, 1e-7) << formulation;
        EXPECT_LT(worst_joint_frame, 1e-7) << formulation;
    }
}

}  // namespace
}  // namespace mbd
