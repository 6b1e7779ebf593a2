// The hopper benchmark's two files (bench/hopper_scene.hpp) describe the same bodies: the mbd
// scene as mbd's loader reads it against the MJCF as written for MuJoCo (names, masses,
// inertias, initial positions, sphere radii and box sizes; MJCF gives half sizes), and the same
// hopper. Speed is never asserted here (docs/benchmarks.md has the numbers).
#include "support/test_support.hpp"

#include "../bench/hopper_scene.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace {

std::vector<double> numbers(const std::string& text) {
    std::vector<double> out;
    std::istringstream in(text);
    for (double v; in >> v;) out.push_back(v);
    return out;
}

TEST(BenchHopper, TheMjcfAndTheMbdSceneDescribeTheSameBodies) {
    hopper::Spec spec;
    spec.spheres = 150;  // a smaller hopper loads in a moment; the writers do not depend on the count
    spec.boxes = 3;
    const mbd::Model model = mbd::test::scene(hopper::mbd_scene(spec), "hopper.yaml");
    const std::string xml = hopper::mjcf(spec, 1e-4);

    const std::regex body(R"re(<body name="(\w+)" pos="([^"]+)"><freejoint/><inertial pos="0 0 0" mass="([^"]+)" )re"
                          R"re(diaginertia="([^"]+)"/><geom type="(\w+)" size="([^"]+)"/></body>)re");
    int count = 0, spheres = 0, boxes = 0;
    for (auto it = std::sregex_iterator(xml.begin(), xml.end(), body); it != std::sregex_iterator(); ++it, ++count) {
        const std::smatch& m = *it;
        ASSERT_LT(count, static_cast<int>(model.bodies.size()));
        const mbd::Body& b = model.bodies[count];
        EXPECT_EQ(m[1].str(), b.name);
        const std::vector<double> pos = numbers(m[2]), inertia = numbers(m[4]), size = numbers(m[6]);
        for (int i = 0; i < 3; ++i) {
            EXPECT_EQ(pos[i], b.position[i]) << b.name;
            EXPECT_EQ(inertia[i], b.inertia(i, i)) << b.name;
        }
        EXPECT_EQ(std::stod(m[3]), b.mass) << b.name;
        if (m[5] == "sphere") {
            ++spheres;
            ASSERT_EQ(size.size(), 1u);
            EXPECT_EQ(size[0], spec.radius);
            EXPECT_NEAR(b.inertia(0, 0), 0.4 * b.mass * spec.radius * spec.radius, 1e-20);  // a solid sphere
        } else {
            ++boxes;
            ASSERT_EQ(size.size(), 3u);  // half sizes: twice them are the scene's edge lengths
            EXPECT_EQ(2 * size[0], spec.box_x);
            EXPECT_EQ(2 * size[1], spec.box_y);
            EXPECT_EQ(2 * size[2], spec.box_z);
        }
    }
    EXPECT_EQ(count, static_cast<int>(model.bodies.size()));
    EXPECT_EQ(spheres, 150);
    EXPECT_EQ(boxes, 3);
    // the scene's shapes: one collision shape each, the spheres' radius and the boxes' edges
    const std::string yaml = hopper::mbd_scene(spec);
    const std::regex sphere("shape: sphere, radius: ([^,]+),"), box(R"(name: b\d+.*\n.*shape: box, size: \[([^\]]+)\])");
    EXPECT_EQ(std::distance(std::sregex_iterator(yaml.begin(), yaml.end(), sphere), std::sregex_iterator()), 150);
    for (auto it = std::sregex_iterator(yaml.begin(), yaml.end(), sphere); it != std::sregex_iterator(); ++it)
        EXPECT_EQ(std::stod((*it)[1]), spec.radius);
    int scene_boxes = 0;
    for (auto it = std::sregex_iterator(yaml.begin(), yaml.end(), box); it != std::sregex_iterator(); ++it, ++scene_boxes)
        EXPECT_EQ(numbers(std::regex_replace((*it)[1].str(), std::regex(","), " ")),
                  (std::vector<double>{spec.box_x, spec.box_y, spec.box_z}));
    EXPECT_EQ(scene_boxes, 3);
    // the hopper and the bin: 12 static boxes in each, the same sizes, centres and orientations
    const std::regex slab(R"re(<geom type="box" size="([^"]+)" pos="([^"]+)" axisangle="([^"]+)"/>)re");
    const std::regex ground_box(
        R"(shape: box, size: \[([^\]]+)\], position: \[([^\]]+)\], orientation: \{axis: \[([^\]]+)\], angle: ([^}]+)\})");
    std::vector<std::vector<double>> in_xml, in_yaml;
    for (auto it = std::sregex_iterator(xml.begin(), xml.end(), slab); it != std::sregex_iterator(); ++it) {
        std::vector<double> v = numbers((*it)[1]), p = numbers((*it)[2]), turn = numbers((*it)[3]);
        for (double& x : v) x *= 2;
        v.insert(v.end(), p.begin(), p.end());
        v.insert(v.end(), turn.begin(), turn.end());  // MJCF in radians (<compiler angle="radian"/>)
        in_xml.push_back(v);
    }
    for (auto it = std::sregex_iterator(yaml.begin(), yaml.end(), ground_box); it != std::sregex_iterator(); ++it) {
        std::vector<double> v = numbers(std::regex_replace((*it)[1].str(), std::regex(","), " "));
        const std::vector<double> p = numbers(std::regex_replace((*it)[2].str(), std::regex(","), " "));
        const std::vector<double> axis = numbers(std::regex_replace((*it)[3].str(), std::regex(","), " "));
        v.insert(v.end(), p.begin(), p.end());
        v.insert(v.end(), axis.begin(), axis.end());
        v.push_back(std::stod((*it)[4]));
        in_yaml.push_back(v);
    }
    EXPECT_EQ(in_xml.size(), 12u);
    EXPECT_EQ(in_xml, in_yaml);
    EXPECT_NE(xml.find("<compiler angle=\"radian\"/>"), std::string::npos);
}

// MuJoCo's contact is matched to mbd's at a sphere resting on the ground: the linear spring K
// (per unit mass) is the Hunt-Crossley law's slope there, and B gives the restitution e.
TEST(BenchHopper, MujocosSpringIsTheHuntCrossleySlopeAtRestAndItsDampingGivesTheRestitution) {
    hopper::Spec spec;
    const hopper::MujocoContact c = hopper::mujoco_contact(spec);
    const double m = spec.sphere_mass, k = spec.stiffness, g = spec.gravity;
    const double delta = std::pow(m * g / k, 2.0 / 3.0);  // k delta^1.5 = m g
    const double h = 1e-9 * delta;                        // the slope by a central difference
    const double slope = (k * std::pow(delta + h, 1.5) - k * std::pow(delta - h, 1.5)) / (2 * h);
    EXPECT_NEAR(c.K * m, slope, 1e-6 * slope);
    // the linear spring-damper x'' = -K x - B x' entered at 1 m/s leaves (x back to 0) at e m/s:
    // integrated here (RK4, 1e5 steps a period)
    const double dt = 2 * M_PI / std::sqrt(c.K) * 1e-5;
    double x = 0.0, v = -1.0;
    auto a = [&](double xx, double vv) { return -c.K * xx - c.B * vv; };
    do {
        const double k1x = v, k1v = a(x, v);
        const double k2x = v + 0.5 * dt * k1v, k2v = a(x + 0.5 * dt * k1x, v + 0.5 * dt * k1v);
        const double k3x = v + 0.5 * dt * k2v, k3v = a(x + 0.5 * dt * k2x, v + 0.5 * dt * k2v);
        const double k4x = v + dt * k3v, k4v = a(x + dt * k3x, v + dt * k3v);
        x += dt / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
        v += dt / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
    } while (x < 0.0);
    EXPECT_NEAR(v, spec.restitution, 1e-4);
}

}  // namespace
