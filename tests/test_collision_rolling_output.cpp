// The rolling resistance's torque in the contact table (issue 39; `mbd simulate --contacts`,
// columns rolling_x, rolling_y, rolling_z: the torque on body j, world axes). Against the closed
// form of a sphere (m, r, I = 2/5 m r^2) rolling along x on a plane with rolling resistance mu_r:
//  - its weight alone presses it, so F_n = m g and the torque is M = -mu_r r m g about y (against
//    the rolling omega_y > 0), nothing about x and z;
//  - rolling without slip, the friction force f on the ball and M decelerate it together:
//    m a = f and I a / r = -r f + M, so f = (5/7) M / r = -(5/7) mu_r m g;
//  - without a coefficient on one material the torque columns are exactly zero.
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace {

using mbd::test::g17;

constexpr double kG = 9.81, kMass = 1.0, kRadius = 0.1, kStiffness = 1e10, kExponent = 1.5, kV0 = 1.0;

// The ball starts at the depth that holds its weight (k d^n = m g), rolling at v0 along x.
std::string rolling_ball(double mu_r_ground) {
    const double depth = std::pow(kMass * kG / kStiffness, 1.0 / kExponent);
    return "dimension: spatial\ngravity: [0, 0, -9.81]\n"
           "ground:\n  collision:\n    - {shape: plane, normal: [0, 0, 1], material: {static_friction: 0.8, "
           "stiction_velocity: 1.0e-5, rolling_resistance: " + g17(mu_r_ground) + "}}\n"
           "bodies:\n  - name: ball\n    mass: " + g17(kMass) + "\n    inertia: [0.004, 0.004, 0.004]\n"
           "    position: [0, 0, " + g17(kRadius - depth) + "]\n    velocity: [" + g17(kV0) + ", 0, 0]\n"
           "    angular_velocity: [0, " + g17(kV0 / kRadius) + ", 0]\n"
           "    collision:\n      - shape: sphere\n        radius: " + g17(kRadius) + "\n"
           "        material: {stiffness: " + g17(kStiffness) + ", exponent: " + g17(kExponent) +
           ", restitution: 0.3, impact_velocity: 0.1, static_friction: 0.8, stiction_velocity: 1.0e-5, "
           "rolling_resistance: 0.1}\n";
}

mbd::test::Csv contacts_of(const std::string& name, const std::string& yaml) {
    const auto dir = mbd::test::scratch(name);
    const auto scene = mbd::test::write_text(dir / "scene.yaml", yaml);
    const auto r = mbd::test::run_mbd("simulate " + scene.string() +
                                      " --t-end 1 --output-step 0.1 --integrator cvode --tol 1e-10 -q --output " +
                                      (dir / "motion.csv").string() + " --contacts " +
                                      (dir / "contacts.csv").string());
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return mbd::test::read_csv(dir / "contacts.csv");
}

TEST(CollisionRollingOutput, TheContactTableCarriesTheRollingTorqueMuRRWeightAgainstTheRolling) {
    const double mu_r = 0.1;  // the ball's; the ground gives 0.2, the pair takes the smaller
    const mbd::test::Csv table = contacts_of("rolling_torque", rolling_ball(0.2));
    const int t = table.column("t"), Fn = table.column("normal_force"), fx = table.column("friction_x");
    const int Mx = table.column("rolling_x"), My = table.column("rolling_y"), Mz = table.column("rolling_z");
    ASSERT_GE(Mx, 0);
    EXPECT_EQ(My, Mx + 1);
    EXPECT_EQ(Mz, Mx + 2);
    EXPECT_EQ(table.header.back(), "rolling_z");
    ASSERT_EQ(table.rows.size(), 11u);  // one contact at each output time, rolling all along (it stops at 1.43 s)
    const double M = mu_r * kRadius * kMass * kG;
    for (const auto& row : table.rows) {
        SCOPED_TRACE("t = " + g17(row[t]));
        EXPECT_NEAR(row[Fn], kMass * kG, 1e-6 * kMass * kG);
        EXPECT_NEAR(row[My], -M, 1e-6 * M);
        EXPECT_NEAR(row[My], -mu_r * kRadius * row[Fn], 1e-12 * M);  // the law's M = mu_r R* F_n, exactly
        EXPECT_LT(std::abs(row[Mx]) + std::abs(row[Mz]), 1e-12 * M);
        // the friction force that decelerates the rolling ball with the torque: (5/7) M / r
        // (at t = 0 the ball starts rolling without the creep friction settles to)
        if (row[t] > 0.0) EXPECT_NEAR(row[fx], -5.0 / 7.0 * M / kRadius, 1e-4 * M / kRadius);
    }
}

TEST(CollisionRollingOutput, WithoutACoefficientOnOneMaterialTheTorqueColumnsAreZero) {
    const mbd::test::Csv table = contacts_of("no_rolling_torque", rolling_ball(0.0));
    ASSERT_EQ(table.rows.size(), 11u);
    for (const auto& row : table.rows)
        for (const char* column : {"rolling_x", "rolling_y", "rolling_z"}) EXPECT_EQ(row[table.column(column)], 0.0);
}

}  // namespace
