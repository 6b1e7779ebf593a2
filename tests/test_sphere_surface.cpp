// The sphere_surface joint (plugins/joints/sphere_surface, book Sec. 8.6) against closed forms: a ball
// rolling and sliding without friction in a spherical bowl. The contact force passes through the
// ball's centre, so the centre moves as a spherical pendulum of length L = R_bowl - r about the
// bowl's centre and the ball's spin stays what it was. Started on the conical-pendulum circle at
// polar angle alpha from the downward vertical, the centre runs round at
//     Omega^2 = g / (L cos(alpha)),
// at constant height, and the normal force is N = m g / cos(alpha) along the ray to the bowl's
// centre (its vertical part carries the weight). The joint has one row per contact, whose
// multiplier is that normal force (book Sec. 8.6: one multiplier survives C_s^T lambda = 0).
#include <mbd/model_system.hpp>
#include <mbd/reactions.hpp>
#include <mbd/simulation.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <string>

#include "support/test_support.hpp"

namespace {

using mbd::Vec3;
using mbd::test::g17;
using mbd::test::shared_registry;

struct ConicalBall {
    double Rb = 1.0, r = 0.1, m = 0.5, g = 9.81, alpha = 0.6;
    Vec3 spin = Vec3(1.0, -2.0, 3.0);  // world, rad/s: slides as it rolls
    double L() const { return Rb - r; }
    double Omega() const { return std::sqrt(g / (L() * std::cos(alpha))); }
    Vec3 centre(double t) const {
        const double rho = L() * std::sin(alpha);
        return Vec3(rho * std::cos(Omega() * t), rho * std::sin(Omega() * t), Rb - L() * std::cos(alpha));
    }
    double N() const { return m * g / std::cos(alpha); }
    std::string scene() const {
        const Vec3 c = centre(0.0);
        const double I = 0.4 * m * r * r;
        return "name: ball-in-bowl\ndimension: spatial\ngravity: [0, 0, -" + g17(g) + "]\nbodies:\n"
               "  - {name: ball, mass: " + g17(m) + ", inertia: [" + g17(I) + ", " + g17(I) + ", " + g17(I) +
               "], position: [" + g17(c.x()) + ", 0, " + g17(c.z()) + "], velocity: [0, " +
               g17(Omega() * L() * std::sin(alpha)) + ", 0], angular_velocity: [" + g17(spin.x()) + ", " +
               g17(spin.y()) + ", " + g17(spin.z()) + "]}\n"
               "joints:\n  - {name: contact, type: sphere_surface, bodies: [ground, ball], point: [0, 0, 0], "
               "axis: [0, 0, 1], radius: " + g17(r) + ", surface: {type: bowl, radius: " + g17(Rb) + "}}\n";
    }
};

TEST(SphereSurface, BallInABowlRunsTheConicalPendulumWithOneNormalMultiplier) {
    const ConicalBall b;
    const mbd::Model model = mbd::test::scene(b.scene());
    mbd::ModelSystem system(model);
    ASSERT_EQ(system.constraint_rows(), 1);  // one row per contact
    mbd::SimulationSettings settings = mbd::test::adaptive_run("augmented", "dopri5", 1e-12, 3.0, 0.01);
    settings.reactions = true;
    double position = 0.0, spin = 0.0, force = 0.0, violation = 0.0;
    int samples = 0;
    mbd::simulate(model, shared_registry(), settings, [&](const mbd::SimulationSample& s) {
        const Vec3 R = s.state.q.head<3>();
        position = std::max(position, (R - b.centre(s.state.t)).norm());
        const mbd::Mat3 A = mbd::rotation_from_euler_parameters(s.state.q.segment<4>(3).normalized());
        spin = std::max(spin, (A * s.state.v.segment<3>(3) - b.spin).norm());
        // the contact's reaction on the ball: N along the ray to the bowl's centre (0, 0, Rb)
        const auto reactions = mbd::joint_reactions(system, s.state, *s.lambda);
        const Vec3 F = reactions[0].on[1].force;
        force = std::max(force, (F - b.N() * (Vec3(0, 0, b.Rb) - R).normalized()).norm());
        mbd::ConstraintValues cv;
        system.constraints(s.state, cv);
        violation = std::max(violation, cv.C.lpNorm<Eigen::Infinity>());
        ++samples;
        return true;
    });
    EXPECT_EQ(samples, 301);
    EXPECT_LE(position, 1e-8);
    EXPECT_LE(spin, 1e-8);
    EXPECT_LE(force, 1e-8 * b.N());
    EXPECT_LE(violation, 1e-10);
    std::cout << "ball in bowl: centre error " << position << " m, spin error " << spin << " rad/s, normal force error "
              << force << " N (N = " << b.N() << "), max |C| " << violation << "\n";
}

// The multiplier is the normal force: the contact row's lambda is -N (compression_sign -1).
TEST(SphereSurface, TheMultiplierIsTheNormalForce) {
    const ConicalBall b;
    const mbd::Model model = mbd::test::scene(b.scene());
    mbd::ModelSystem system(model);
    mbd::Param node;
    auto formulation = mbd::test::make_formulation("augmented", node);
    formulation->bind(system, mbd::FormulationOptions{});
    mbd::State s = system.initial_state();
    system.assemble(s);
    system.consistent_velocities(s);
    Eigen::VectorXd lambda;
    formulation->multipliers(s, lambda);
    ASSERT_EQ(lambda.size(), 1);
    EXPECT_NEAR(lambda[0], -b.N(), 1e-10 * b.N());
}

TEST(SphereSurface, BadKeysAreNamed) {
    const ConicalBall b;
    const std::string good = b.scene();
    auto error_of = [&](const std::string& from, const std::string& to) {
        try {
            mbd::test::scene(mbd::test::replaced(good, from, to));
        } catch (const std::exception& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_NE(error_of("type: bowl", "type: cone").find("unknown surface type 'cone'"), std::string::npos);
    EXPECT_NE(error_of("type: bowl, radius: 1}", "type: bowl, radius: 0.05}").find("must exceed the ball's radius"),
              std::string::npos);
}

}  // namespace
