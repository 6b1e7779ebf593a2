// `mbd plugin check`: passes our own plugins, fails a deliberately broken one
// for the right reason, and refuses a plugin of another ABI.
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace mbd {
namespace {

std::string plugin(const std::string& file) { return (test::build_plugin_dir() / file).string(); }
std::string test_plugin(const std::string& file) { return (std::filesystem::path(MBD_TEST_PLUGIN_DIR) / file).string(); }

TEST(PluginCheck, StandardJointAndForcePluginsPass) {
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"libmbd_joint_revolute.so", ""},
        {"libmbd_joint_distance.so", ""},       // planar only; its `points` are drawn at random
        {"libmbd_joint_prismatic.so", ""},
        {"libmbd_joint_universal.so", ""},      // spatial only; random perpendicular `axes`
        {"libmbd_joint_screw.so", " --params 'pitch: 0.02'"},
        {"libmbd_joint_rolling_disc.so", " --params 'radius: 0.3'"},  // velocity-level rows
        {"libmbd_force_spring_damper.so", " --params 'stiffness: 100' --params 'damping: 2'"},
        {"libmbd_force_point_force.so", " --params 'force: [1, -2]'"},  // planar components: planar only
        {"libmbd_force_gravity.so", ""}};
    for (const auto& [lib, params] : cases) {
        const auto r = test::run_mbd("plugin check " + plugin(lib) + params);
        EXPECT_EQ(r.exit_code, 0) << lib << "\n" << r.out << r.err;
        EXPECT_NE(r.out.find(" 0 failed"), std::string::npos) << r.out;
    }
}

// A type that describes its keys is checked from its description alone; --params replaces
// the examples (gear_pair: `ratio` instead of the example's `radii`, which it excludes).
TEST(PluginCheck, GearPairPassesFromItsDescriptionAndWithEitherKey) {
    const auto without = test::run_mbd("plugin check " + plugin("libmbd_joint_gear_pair.so"));
    EXPECT_EQ(without.exit_code, 0) << without.out << without.err;
    EXPECT_NE(without.out.find("2 checked, 0 failed"), std::string::npos) << without.out;
    const auto with = test::run_mbd("plugin check " + plugin("libmbd_joint_gear_pair.so") + " --params 'ratio: -2'");
    EXPECT_EQ(with.exit_code, 0) << with.out << with.err;
    EXPECT_NE(with.out.find("2 checked, 0 failed"), std::string::npos) << with.out;
}

// A plugin built without a key description (tests/plugins/drag_without_jacobians.cpp needs
// `coefficient`) is checked as before: without --params it fails, saying how to pass its keys.
TEST(PluginCheck, ATypeWithoutDescriptionNeedsParams) {
    const auto r = test::run_mbd("plugin check " + test_plugin("libmbd_force_quadratic_drag.so"));
    EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
    EXPECT_NE(r.out.find("it describes no keys"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("--params 'key: value'"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("missing key 'coefficient'"), std::string::npos) << r.out;
}

// The contact joints with surface parameters eliminated inside (cam, sphere_surface, wheel_rail): every
// follower and profile type on random states off the constraint manifold.
// 25 points [x, f] of a circular arc of radius 0.3 with its top f = top at x = 0, |x| <= 0.29.
std::string circle_points(double top) {
    std::string out = "[";
    for (int k = -12; k <= 12; ++k) {
        const double x = 0.29 * k / 12.0;
        out += (k == -12 ? "[" : ", [") + test::g17(x) + ", " + test::g17(top - 0.3 + std::sqrt(0.09 - x * x)) + "]";
    }
    return out + "]";
}

TEST(PluginCheck, ContactJointsPassForEveryFollowerAndSurface) {
    const std::string spline = " --params 'profile: {type: spline, radii: [0.3, 0.31, 0.33, 0.32, 0.3, 0.29, 0.28, 0.29]}'";
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"libmbd_joint_cam.so", " --params 'follower: knife_edge' --params 'follower_point: [0.1, 0]'"
                                " --params 'profile: {type: harmonic, base: 0.3, cos: [0.03, 0.01], sin: [0, 0.005]}'"},
        {"libmbd_joint_cam.so", " --params 'follower: roller' --params 'radius: 0.05' --params 'follower_point: [0, 0]'"
                                " --params 'profile: {type: eccentric, radius: 0.3, eccentricity: 0.05}'"},
        {"libmbd_joint_cam.so", " --params 'follower: roller' --params 'radius: 0.05' --params 'follower_point: [0, 0]'" + spline},
        {"libmbd_joint_cam.so", " --params 'follower: flat_face' --params 'face_normal: [0.3, -1]'"
                                " --params 'follower_point: [0, 0.1]'" + spline},
        {"libmbd_joint_sphere_surface.so", " --params 'radius: 0.1' --params 'surface: {type: paraboloid, curvatures: [0.5, -0.3]}'"},
        {"libmbd_joint_sphere_surface.so", " --params 'radius: 0.1' --params 'surface: {type: bowl, radius: 3}'"},
        // the random joint geometry puts the contact far along the axle from the wheel's centre
        // (up to 1.6 m on the cones, 24 m on the tilted cylinder, whose lowest point runs towards
        // its end): wide treads (the default 2 r0 = 0.9 m would leave the contact off the tread)
        {"libmbd_joint_wheel_rail.so", " --params 'wheel: {type: cone, radius: 0.45, cone_angle: 0.05, width: 10}'"
                                       " --params 'rail: {type: arc, radius: 0.3}'"},
        {"libmbd_joint_wheel_rail.so", " --params 'wheel: {type: cone, radius: 0.45, width: 100}' --params 'rail: {type: arc, radius: 0.3}'"
                                       " --params 'wheel_centre: [0.8, -0.2, 0.3]' --params 'axle: [0.1, 1, 0.2]'"},
        // a toroidal tread (crown radius 0.3 m) on a flat head, and a cone on a spline crown: the
        // splines span slopes beyond the random states' tilts (past their ends they are straight)
        {"libmbd_joint_wheel_rail.so", " --params 'wheel: {type: spline, points: " + circle_points(0.45) + "}'"
                                       " --params 'rail: {type: flat}'"},
        {"libmbd_joint_wheel_rail.so", " --params 'wheel: {type: cone, radius: 0.45, cone_angle: -0.1, width: 10}'"
                                       " --params 'rail: {type: spline, points: " + circle_points(0.0) + "}'"}};
    for (const auto& [lib, params] : cases) {
        const auto r = test::run_mbd("plugin check " + plugin(lib) + params);
        EXPECT_EQ(r.exit_code, 0) << lib << params << "\n" << r.out << r.err;
        EXPECT_NE(r.out.find("2 checked, 0 failed"), std::string::npos) << r.out;
    }
}

TEST(PluginCheck, BrokenGammaFailsForThatReasonOnly) {
    const auto r = test::run_mbd("plugin check " + test_plugin("libmbd_joint_broken_pin.so"));
    EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
    EXPECT_NE(r.out.find("FAIL  joint 'broken_pin' (planar)"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("gamma (Cddot = J vdot - gamma)"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("exceeds tolerance"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("state showing it: t = "), std::string::npos) << r.out;
    // the Jacobian itself is right: its line must not be flagged
    const size_t jac = r.out.find("Jacobian dC/dq");
    ASSERT_NE(jac, std::string::npos) << r.out;
    const std::string jac_line = r.out.substr(jac, r.out.find('\n', jac) - jac);
    EXPECT_EQ(jac_line.find("exceeds"), std::string::npos) << jac_line;
}

TEST(PluginCheck, BrokenVelocityRowGammaFailsForThatReasonOnly) {
    const auto r = test::run_mbd("plugin check " + test_plugin("libmbd_joint_broken_skate.so"));
    EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
    EXPECT_NE(r.out.find("FAIL  joint 'broken_skate' (spatial)"), std::string::npos) << r.out;
    const size_t gamma = r.out.find("gamma_v (d/dt(A v - b) = A vdot - gamma_v)");
    ASSERT_NE(gamma, std::string::npos) << r.out;
    EXPECT_NE(r.out.substr(gamma, r.out.find('\n', gamma) - gamma).find("exceeds tolerance"), std::string::npos) << r.out;
    // A and b do not depend on v: that line is not flagged (absent when zero)
    const size_t linear = r.out.find("A, b independent of v");
    if (linear != std::string::npos)
        EXPECT_EQ(r.out.substr(linear, r.out.find('\n', linear) - linear).find("exceeds"), std::string::npos) << r.out;
}

// A friction element's moment must be affine in its load (Force::evaluate_at_load): the
// shipped ones are, a fixture whose moment grows with the square of the load is caught by that
// check alone.
TEST(PluginCheck, FrictionLoadMustBeAffine) {
    for (const char* lib : {"libmbd_force_rotational_friction.so"}) {
        const auto r = test::run_mbd("plugin check " + plugin(lib) +
                                     " --params 'radius: 0.05' --params 'normal_force: 20' --params 'static_friction: 0.3'"
                                     " --params 'kinetic_friction: 0.2' --params 'preload: 0.1'");
        EXPECT_EQ(r.exit_code, 0) << lib << "\n" << r.out << r.err;
        EXPECT_NE(r.out.find(" 0 failed"), std::string::npos) << r.out;
    }
    const auto r = test::run_mbd("plugin check " + test_plugin("libmbd_force_broken_load_friction.so"));
    EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
    EXPECT_NE(r.out.find("FAIL  force 'broken_load_friction' (planar)"), std::string::npos) << r.out;
    const size_t load = r.out.find("Q affine in the load (evaluate_at_load)");
    ASSERT_NE(load, std::string::npos) << r.out;
    EXPECT_NE(r.out.substr(load, r.out.find('\n', load) - load).find("exceeds tolerance"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("dQ/dv"), std::string::npos) << r.out;  // no Jacobians: nothing else flagged
}

TEST(PluginCheck, RandomGeometryIsSeededAndReproducible) {
    // the same seed gives the same report, digit for digit; another seed other states and geometry
    const std::string lib = plugin("libmbd_joint_distance.so");
    const auto a = test::run_mbd("plugin check " + lib + " --seed 7");
    const auto b = test::run_mbd("plugin check " + lib + " --seed 7");
    const auto c = test::run_mbd("plugin check " + lib + " --seed 8");
    ASSERT_EQ(a.exit_code, 0) << a.out << a.err;
    EXPECT_NE(a.out.find("seed 7"), std::string::npos) << a.out;
    EXPECT_EQ(a.out, b.out);
    EXPECT_EQ(c.exit_code, 0) << c.out << c.err;
    EXPECT_NE(c.out.substr(c.out.find('\n')), a.out.substr(a.out.find('\n'))) << "the seed must change the checks";
}

TEST(PluginCheck, WrongAbiIsRefused) {
    const auto r = test::run_mbd("plugin check " + test_plugin("libmbd_joint_wrong_abi.so"));
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.out.find("ABI 999"), std::string::npos) << r.out;
}

TEST(PluginCheck, NotAPluginIsRefused) {
    const auto r = test::run_mbd("plugin check " + (std::filesystem::path(MBD_BUILD_DIR) / "lib/libmbd_core.so").string());
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.out.find("exports no mbd plugin type"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace mbd
