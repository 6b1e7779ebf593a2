// Rolling resistance of collision materials (issue 39 item 1; `rolling_resistance` mu_r,
// plugins/forces/collision_contact/collision_material.hpp rolling_torque): a torque
// M = mu_r R* F_n against the rolling angular velocity. Against closed forms:
//  - a sphere (m, r, I = 2/5 m r^2) rolling on a plane without slip: the torque balance about
//    the contact point, (I + m r^2) w' = -M with M = mu_r r m g, gives the deceleration
//    a = mu_r r m g r / (I + m r^2) = (5/7) mu_r g; it stops at t = v0 / a after v0^2 / (2 a);
//  - with mu_r = 0 on one material (the pair takes the smaller) it rolls on at v0;
//  - a negative coefficient is refused naming the body.
#include "support/test_support.hpp"

#include <mbd/simulation.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace {

using mbd::test::g17;

constexpr double kG = 9.81, kMass = 1.0, kRadius = 0.1, kStiffness = 1e10, kExponent = 1.5, kV0 = 1.0;

// The ball starts at the depth that holds its weight (k d^n = m g), rolling at v0 along x.
std::string rolling_ball(double mu_r_ball, double mu_r_ground) {
    const double depth = std::pow(kMass * kG / kStiffness, 1.0 / kExponent);
    return "dimension: spatial\ngravity: [0, 0, -9.81]\n"
           "ground:\n  collision:\n    - {shape: plane, normal: [0, 0, 1], material: {static_friction: 0.8, "
           "stiction_velocity: 1.0e-5, rolling_resistance: " + g17(mu_r_ground) + "}}\n"
           "bodies:\n  - name: ball\n    mass: 1\n    inertia: [0.004, 0.004, 0.004]\n"
           "    position: [0, 0, " + g17(kRadius - depth) + "]\n    velocity: [" + g17(kV0) + ", 0, 0]\n"
           "    angular_velocity: [0, " + g17(kV0 / kRadius) + ", 0]\n"
           "    collision:\n      - shape: sphere\n        radius: 0.1\n"
           "        material: {stiffness: 1.0e10, exponent: 1.5, restitution: 0.3, impact_velocity: 0.1, "
           "static_friction: 0.8, stiction_velocity: 1.0e-5, rolling_resistance: " + g17(mu_r_ball) + "}\n";
}

struct Samples {
    std::vector<double> t, x, vx, wy;
};

Samples roll(const std::string& yaml, double t_end) {
    const mbd::Model model = mbd::test::scene(yaml);
    Samples s;
    mbd::simulate(model, mbd::test::shared_registry(), mbd::test::adaptive_run("augmented", "cvode", 1e-10, t_end, 0.1),
                  [&](const mbd::SimulationSample& x) {
                      s.t.push_back(x.state.t);
                      s.x.push_back(x.state.q[0]);
                      s.vx.push_back(x.state.v[0]);
                      s.wy.push_back(x.state.v[4]);  // body axes; the ball does not turn about x or z
                      return true;
                  });
    return s;
}

TEST(RollingResistance, ARollingSphereDeceleratesAtFiveSeventhsOfMuRGAndStops) {
    const double mu_r = 0.1;
    const Samples s = roll(rolling_ball(mu_r, 0.2), 2.0);  // the pair takes the smaller mu_r
    const double a = 5.0 / 7.0 * mu_r * kG;
    const double t_stop = kV0 / a;  // 1.43 s
    ASSERT_EQ(s.t.size(), 21u);
    // rows 2 and 12 (t = 0.2, 1.2): rolling, before the stop
    const double measured = (s.vx[2] - s.vx[12]) / (s.t[12] - s.t[2]);
    EXPECT_NEAR(measured, a, 1e-4 * a);
    EXPECT_NEAR(s.vx[12], kV0 - a * s.t[12], 1e-4 * kV0);
    EXPECT_NEAR(s.wy[12] * kRadius, s.vx[12], 1e-4 * kV0) << "it rolls without slipping";
    EXPECT_LT(t_stop, s.t.back() - 0.3);
    EXPECT_LT(std::abs(s.vx.back()), 1e-6) << "stopped";
    EXPECT_LT(std::abs(s.wy.back()) * kRadius, 1e-6);
    EXPECT_NEAR(s.x.back() - s.x.front(), kV0 * kV0 / (2 * a), 1e-4 * kV0 * kV0 / (2 * a));
    RecordProperty("deceleration_error", g17(measured / a - 1));
}

TEST(RollingResistance, WithoutACoefficientOnOneMaterialTheSphereRollsOn) {
    // (to the contact's depth: rolling on its contact point d = 1e-6 m below r, the ball's start,
    // w = v0 / r, slips by v0 d / r until friction matches them, a change of that order)
    const Samples s = roll(rolling_ball(0.1, 0.0), 1.0);
    EXPECT_NEAR(s.vx.back(), kV0, 1e-4 * kV0);
    EXPECT_NEAR(s.wy.back() * kRadius, kV0, 1e-4 * kV0);
}

TEST(RollingResistance, ANegativeCoefficientIsRefusedNamingTheBody) {
    try {
        mbd::test::scene(rolling_ball(-0.1, 0.1));
        ADD_FAILURE() << "a negative rolling_resistance was accepted";
    } catch (const mbd::InputError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("ball"), std::string::npos) << message;
        EXPECT_NE(message.find("rolling_resistance"), std::string::npos) << message;
    }
}

}  // namespace
