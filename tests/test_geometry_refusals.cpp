// Geometry that cannot work is refused at load, naming the element and where it fails (issue
// 42, item 3): a compliant contact that starts deeper than its radius, a cam profile that is not
// convex, a joint stop on a coordinate its joint does not have. (A wheel leaving its rail head
// during a run: test_wheel_rail.cpp.)
#include <mbd/scene.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "support/test_support.hpp"

namespace {

using mbd::test::g17;

// The message of the InputError loading `yaml` throws, or "loaded".
std::string load_error(const std::string& yaml) {
    try {
        mbd::test::scene(yaml);
    } catch (const mbd::InputError& e) {
        return e.what();
    }
    return "loaded";
}

#define EXPECT_CONTAINS(text, part) \
    EXPECT_NE(std::string(text).find(part), std::string::npos) << "'" << (text) << "' lacks '" << (part) << "'"

// ------------------------------------------------------------------ contacts
// A ball of radius r whose centre is `overlap - r` below the line or plane y (z) = 0, so the
// shapes overlap by `overlap`.
std::string ball_in_floor(const std::string& type, double r, double overlap) {
    const bool planar = type == "circle_line";
    const std::string h = g17(r - overlap);
    return std::string("dimension: ") + (planar ? "planar" : "spatial") + "\nbodies:\n  - {name: ball, mass: 1, inertia: " +
           (planar ? "0.004" : "[0.004, 0.004, 0.004]") + ", position: " + (planar ? "[0, " + h + "]" : "[0, 0, " + h + "]") +
           "}\nforces:\n  - {name: floor, type: " + type + ", bodies: [ground, ball], normal: " +
           (planar ? "[0, 1]" : "[0, 0, 1]") + ", radius: " + g17(r) + ", stiffness: 1e6}\n";
}

// Balls of radii 0.2 (a, at the origin) and 0.1 (b) whose shapes overlap by `overlap`.
std::string balls_overlapping(const std::string& type, double overlap) {
    const bool planar = type == "circle_circle";
    const std::string x = g17(0.3 - overlap);
    const std::string inertia = planar ? "0.004" : "[0.004, 0.004, 0.004]";
    return std::string("dimension: ") + (planar ? "planar" : "spatial") + "\nbodies:\n"
           "  - {name: a, mass: 1, inertia: " + inertia + ", position: " + (planar ? "[0, 0]" : "[0, 0, 0]") + "}\n"
           "  - {name: b, mass: 1, inertia: " + inertia + ", position: " + (planar ? "[" + x + ", 0]" : "[" + x + ", 0, 0]") +
           "}\nforces:\n  - {name: hit, type: " + type + ", bodies: [a, b], radii: [0.2, 0.1], stiffness: 1e6}\n";
}

TEST(GeometryRefusals, AContactStartingTenMetresDeepIsRefusedWithItsDepth) {
    // the case: a circle 10 m inside the half-plane (it left at 94 m/s)
    const std::string message = load_error(ball_in_floor("circle_line", 0.1, 10.1));
    EXPECT_CONTAINS(message, "test.yaml:");
    EXPECT_CONTAINS(message, "force 'floor': the shapes overlap by 10.1 m at t = 0, more than the circle's radius 0.1 m");
}

TEST(GeometryRefusals, AnOverlapIsAllowedUpToTheRadiusOfEveryContactType) {
    for (const char* type : {"circle_line", "sphere_plane"}) {
        EXPECT_EQ(load_error(ball_in_floor(type, 0.1, 0.09)), "loaded") << type;
        EXPECT_CONTAINS(load_error(ball_in_floor(type, 0.1, 0.11)), "overlap by 0.11 m at t = 0") << type;
    }
    // two spheres: the smaller radius (0.1) bounds the overlap, not the larger or their sum
    for (const char* type : {"circle_circle", "sphere_sphere"}) {
        EXPECT_EQ(load_error(balls_overlapping(type, 0.09)), "loaded") << type;
        const std::string message = load_error(balls_overlapping(type, 0.15));
        EXPECT_CONTAINS(message, "force 'hit': the shapes overlap by 0.15 m at t = 0") << type;
        EXPECT_CONTAINS(message, "smaller") << type;
    }
}

// ------------------------------------------------------------------ cams
std::string cam_with(const std::string& profile) {
    return "dimension: planar\nbodies:\n"
           "  - {name: cam, mass: 1, inertia: 0.01, position: [0, 0]}\n"
           "  - {name: follower, mass: 0.2, inertia: 0.001, position: [0, 0.2]}\n"
           "joints:\n"
           "  - {name: bearing, type: revolute, bodies: [ground, cam], point: [0, 0]}\n"
           "  - {name: guide, type: prismatic, bodies: [ground, follower], point: [0, 0.2], axis: [0, 1]}\n"
           "  - {name: lobe, type: cam, bodies: [cam, follower], point: [0, 0], follower: knife_edge, "
           "follower_point: [0, -0.1], profile: " + profile + "}\n";
}

TEST(GeometryRefusals, ANonConvexCamIsRefusedWhereItIsMostHollow) {
    // d = 0.1 + 0.02 cos 4 phi: at phi = pi/4 (d = 0.08, d' = 0, d'' = 0.32) the polar
    // curvature (d^2 + 2 d'^2 - d d'') / (d^2 + d'^2)^1.5 is (0.0064 - 0.0256) / 0.08^3 = -37.5 1/m
    const std::string message = load_error(cam_with("{type: harmonic, base: 0.1, cos: [0, 0, 0, 0.02]}"));
    EXPECT_CONTAINS(message, "cam 'lobe': the profile is not convex: at phi = 0.785398 rad (radius 0.08 m)");
    EXPECT_CONTAINS(message, "curvature -37.5 1/m");
    // a spline with one dented radius (at phi = 2 pi 2 / 8 = pi / 2) is refused there
    EXPECT_CONTAINS(load_error(cam_with("{type: spline, radii: [0.1, 0.1, 0.06, 0.1, 0.1, 0.1, 0.1, 0.1]}")),
                    "not convex: at phi = 1.5708 rad (radius 0.06 m)");
    // d = 0.1 + 0.005 cos 4 phi: d^2 - d d'' = 0.095^2 - 0.095 * 0.08 > 0 at its flattest: convex
    EXPECT_EQ(load_error(cam_with("{type: harmonic, base: 0.1, cos: [0, 0, 0, 0.005]}")), "loaded");
}

// ------------------------------------------------------------------ joint stops
std::string stop_on(const std::string& joint_type, const std::string& coordinate) {
    return "dimension: planar\nbodies:\n  - {name: arm, mass: 1, inertia: 0.01, position: [0.5, 0]}\n"
           "joints:\n  - {name: pin, type: " + joint_type + ", bodies: [ground, arm], point: [0, 0]" +
           (joint_type == "prismatic" ? ", axis: [1, 0]" : "") + "}\n"
           "forces:\n  - {name: stop, type: joint_stop, bodies: [ground, arm], point: [0, 0], coordinate: " + coordinate +
           ", upper: 0.3, restitution: 0.5}\n";
}

TEST(GeometryRefusals, AStopOnACoordinateItsJointLacksIsRefusedNamingBoth) {
    const std::string travel_on_revolute = load_error(stop_on("revolute", "travel"));
    EXPECT_CONTAINS(travel_on_revolute, "test.yaml:");
    EXPECT_CONTAINS(travel_on_revolute, "force 'stop': 'coordinate: travel', but joint 'pin' (revolute) between its "
                                        "bodies has an angle ('coordinate: angle'), so the stop would never act");
    EXPECT_CONTAINS(load_error(stop_on("prismatic", "angle")),
                    "'coordinate: angle', but joint 'pin' (prismatic) between its bodies has a travel");
    EXPECT_EQ(load_error(stop_on("revolute", "angle")), "loaded");
    EXPECT_EQ(load_error(stop_on("prismatic", "travel")), "loaded");
}

}  // namespace
