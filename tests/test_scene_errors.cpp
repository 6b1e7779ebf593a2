// Scene loader: every bad input gives an InputError at file:line naming the
// offending key or element; good scenes load with coincident joint markers.
#include "support/test_paths.hpp"
#include <mbd/scene.hpp>
#include <mbd/simulation.hpp>

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

mbd::Registry& registry() {
    static mbd::Registry instance({std::filesystem::path(MBD_BUILD_DIR) / "lib/mbd/plugins"});
    return instance;
}

const char* kLabel = "test.yaml";

// The what() of the InputError the scene throws ("" and a test failure if none).
std::string load_error(const std::string& yaml) {
    try {
        mbd::load_scene_text(yaml, kLabel, registry());
    } catch (const mbd::InputError& e) {
        return e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << "expected mbd::InputError, got another exception: " << e.what();
        return {};
    }
    ADD_FAILURE() << "expected mbd::InputError, the scene loaded";
    return {};
}

std::string at_line(int line) { return std::string(kLabel) + ":" + std::to_string(line); }

#define EXPECT_CONTAINS(text, part) \
    EXPECT_NE(std::string(text).find(part), std::string::npos) << "'" << (text) << "' lacks '" << (part) << "'"

// A valid planar scene (no forces, so it needs joint plugins only). Line numbers
// matter to the tests below: they edit single lines of it.
const std::string kPlanar = R"(name: slider-crank
dimension: planar
bodies:
  - name: crank
    mass: 1
    inertia: 0.01
    position: [0.1, 0]
    angle: 0
  - name: rod
    mass: 1
    inertia: 0.05
    position: [0.3, 0]
    angle: 0
joints:
  - {name: O, type: revolute, bodies: [ground, crank], point: [0, 0]}
  - {name: A, type: revolute, bodies: [crank, rod], point: [0.2, 0]}
drivers:
  - {name: motor, joint: O, motion: {type: linear, initial: 0, rate: 1}}
)";

std::string replace(std::string text, const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << "test bug: '" << from << "' not in the scene";
    if (at != std::string::npos) text.replace(at, from.size(), to);
    return text;
}

}  // namespace

TEST(SceneErrors, MalformedYaml) {
    const std::string msg = load_error("dimension: planar\nbodies:\n  - name: a\n    mass: [1, 2\n  - name: b\n");
    EXPECT_CONTAINS(msg, std::string(kLabel) + ":");
    EXPECT_CONTAINS(msg, "YAML");
    // the unterminated flow list starts at line 4; yaml-cpp reports it at or after that line
    bool line_ok = false;
    for (int line = 4; line <= 6; ++line) line_ok = line_ok || msg.find(at_line(line)) != std::string::npos;
    EXPECT_TRUE(line_ok) << msg;
}

TEST(SceneErrors, MalformedYamlBadIndentation) {
    const std::string msg = load_error("dimension: planar\nbodies:\n  - name: a\n   mass: 1\n");
    EXPECT_CONTAINS(msg, "YAML");
    EXPECT_CONTAINS(msg, std::string(kLabel) + ":4");
}

TEST(SceneErrors, UnknownTopLevelKeySuggests) {
    const std::string msg = load_error(replace(kPlanar, "dimension: planar\n", "dimension: planar\ngravty: [0, -9.81]\n"));
    EXPECT_CONTAINS(msg, at_line(3));
    EXPECT_CONTAINS(msg, "unknown key 'gravty' in scene");
    EXPECT_CONTAINS(msg, "did you mean 'gravity'?");
}

TEST(SceneErrors, UnknownBodyKeySuggests) {
    const std::string msg = load_error(replace(kPlanar, "    inertia: 0.05\n", "    inertia: 0.05\n    positon: [0, 0]\n"));
    EXPECT_CONTAINS(msg, at_line(12));
    EXPECT_CONTAINS(msg, "'positon'");
    EXPECT_CONTAINS(msg, "body 'rod'");
    EXPECT_CONTAINS(msg, "did you mean 'position'?");
}

TEST(SceneErrors, OrientationInPlanarBody) {
    const std::string msg = load_error(replace(kPlanar, "    angle: 0\n  - name: rod", "    orientation: 0\n  - name: rod"));
    EXPECT_CONTAINS(msg, at_line(8));
    EXPECT_CONTAINS(msg, "'orientation'");
    EXPECT_CONTAINS(msg, "'angle'");
}

TEST(SceneErrors, UnknownJointKeySuggests) {
    const std::string msg = load_error(replace(kPlanar, "bodies: [crank, rod], point: [0.2, 0]}",
                                               "bodies: [crank, rod],\n      pont: [0.2, 0]}"));
    EXPECT_CONTAINS(msg, at_line(17));
    EXPECT_CONTAINS(msg, "unknown key 'pont' in joint 'A'");
    EXPECT_CONTAINS(msg, "did you mean 'point'?");
}

TEST(SceneErrors, UnknownJointKeySuggestsPluginKey) {
    // 'pitch' is accepted only because the screw plugin asked for it
    const std::string msg = load_error(R"(dimension: spatial
bodies:
  - {name: nut, mass: 1, inertia: [1, 1, 1], position: [0, 0, 0]}
joints:
  - name: s
    type: screw
    bodies: [ground, nut]
    axis: [0, 0, 1]
    pitch: 0.01
    pitchh: 0.02
)");
    EXPECT_CONTAINS(msg, at_line(10));
    EXPECT_CONTAINS(msg, "unknown key 'pitchh' in joint 's'");
    EXPECT_CONTAINS(msg, "did you mean 'pitch'?");
}

TEST(SceneErrors, MisspeltPluginKeyIsNamedWhenThePluginFails) {
    const std::string msg = load_error(R"(dimension: planar
bodies:
  - {name: g1, mass: 1, inertia: 1, position: [0, 0]}
  - {name: g2, mass: 1, inertia: 1, position: [1, 0]}
joints:
  - name: mesh
    type: gear_pair
    bodies: [g1, g2]
    radiii: [0.1, 0.2]
)");
    EXPECT_CONTAINS(msg, "'radiii'");
    EXPECT_CONTAINS(msg, "did you mean 'radii'?");
    EXPECT_CONTAINS(msg, "line 9");
}

TEST(SceneErrors, UndefinedBodyInJointListsBodies) {
    const std::string msg = load_error(replace(kPlanar, "bodies: [crank, rod]", "bodies: [crank, rood]"));
    EXPECT_CONTAINS(msg, at_line(16));
    EXPECT_CONTAINS(msg, "joint 'A'");
    EXPECT_CONTAINS(msg, "undefined body 'rood'");
    EXPECT_CONTAINS(msg, "'ground', 'crank', 'rod'");
}

TEST(SceneErrors, UnknownJointTypeListsKnownTypes) {
    const std::string msg = load_error(replace(kPlanar, "{name: A, type: revolute", "{name: A, type: hinge"));
    EXPECT_CONTAINS(msg, at_line(16));
    EXPECT_CONTAINS(msg, "'hinge'");
    EXPECT_CONTAINS(msg, "revolute");
    EXPECT_CONTAINS(msg, "prismatic");
}

TEST(SceneErrors, ZeroMassLoadsButDynamicsRefusesItByName) {
    // a massless body is valid input for kinematics and statics; forward dynamics would need
    // M^-1, so it stops before any work, naming the body and what to do
    const mbd::Model model = mbd::load_scene_text(
        replace(kPlanar, "    mass: 1\n    inertia: 0.05", "    mass: 0\n    inertia: 0"), kLabel, registry());
    EXPECT_EQ(model.bodies[1].mass, 0.0);
    mbd::SimulationSettings settings;
    settings.t_end = 0.1;
    settings.progress = false;
    try {
        mbd::simulate(model, registry(), settings, [](const mbd::SimulationSample&) { return true; });
        ADD_FAILURE() << "the simulation of a massless body ran";
    } catch (const mbd::DynamicsError& e) {
        EXPECT_CONTAINS(e.what(), "body 'rod' has zero mass");
        EXPECT_CONTAINS(e.what(), "mass matrix is singular");
        EXPECT_CONTAINS(e.what(), "give it a mass");
    }
}

TEST(SceneErrors, NegativeMass) {
    const std::string msg = load_error(replace(kPlanar, "    mass: 1\n    inertia: 0.01", "    mass: -2\n    inertia: 0.01"));
    EXPECT_CONTAINS(msg, at_line(5));
    EXPECT_CONTAINS(msg, "body 'crank'");
    EXPECT_CONTAINS(msg, "'mass'");
}

TEST(SceneErrors, NonPositiveInertiaPlanar) {
    const std::string msg = load_error(replace(kPlanar, "inertia: 0.05", "inertia: -0.05"));
    EXPECT_CONTAINS(msg, at_line(11));
    EXPECT_CONTAINS(msg, "body 'rod'");
    EXPECT_CONTAINS(msg, "'inertia' must be positive");
}

TEST(SceneErrors, NonPositiveInertiaSpatial) {
    const std::string msg = load_error(R"(dimension: spatial
bodies:
  - name: box
    mass: 1
    inertia: [1,
              -1,
              1]
)");
    EXPECT_CONTAINS(msg, at_line(6));
    EXPECT_CONTAINS(msg, "body 'box'");
    EXPECT_CONTAINS(msg, "inertia");
}

TEST(SceneErrors, InertiaMatrixNotPositiveDefinite) {
    const std::string msg = load_error(R"(dimension: spatial
bodies:
  - name: box
    mass: 1
    inertia: [[1, 0, 0], [0, 1, 2], [0, 2, 1]]
)");
    EXPECT_CONTAINS(msg, at_line(5));
    EXPECT_CONTAINS(msg, "positive semi-definite");
}

TEST(SceneErrors, ZeroAxis) {
    const std::string msg = load_error(R"(dimension: spatial
bodies:
  - {name: wheel, mass: 1, inertia: [1, 1, 1], position: [0, 0, 0]}
joints:
  - name: hub
    type: revolute
    bodies: [ground, wheel]
    point: [0, 0, 0]
    axis: [0, 0, 0]
)");
    EXPECT_CONTAINS(msg, at_line(9));
    EXPECT_CONTAINS(msg, "joint 'hub'");
    EXPECT_CONTAINS(msg, "'axis' must not be the zero vector");
}

TEST(SceneErrors, XAxisParallelToAxis) {
    const std::string msg = load_error(R"(dimension: spatial
bodies:
  - {name: wheel, mass: 1, inertia: [1, 1, 1], position: [0, 0, 0]}
joints:
  - name: hub
    type: revolute
    bodies: [ground, wheel]
    axis: [0, 0, 1]
    x_axis: [0, 0, -2]
)");
    EXPECT_CONTAINS(msg, at_line(9));
    EXPECT_CONTAINS(msg, "parallel");
}

TEST(SceneErrors, UniversalAxesNotPerpendicular) {
    const std::string msg = load_error(R"(dimension: spatial
bodies:
  - {name: link, mass: 1, inertia: [1, 1, 1], position: [0, 0, -1]}
joints:
  - name: hooke
    type: universal
    bodies: [ground, link]
    point: [0, 0, 0]
    axes: [[1, 0, 0], [1, 1, 0]]
)");
    EXPECT_CONTAINS(msg, at_line(9));
    EXPECT_CONTAINS(msg, "perpendicular");
}

TEST(SceneErrors, DuplicateBodyName) {
    const std::string msg = load_error(replace(kPlanar, "name: rod", "name: crank"));
    EXPECT_CONTAINS(msg, at_line(9));
    EXPECT_CONTAINS(msg, "duplicate body name 'crank'");
}

TEST(SceneErrors, GroundIsReserved) {
    const std::string msg = load_error(replace(kPlanar, "name: rod", "name: ground"));
    EXPECT_CONTAINS(msg, at_line(9));
    EXPECT_CONTAINS(msg, "'ground'");
}

TEST(SceneErrors, DuplicateJointName) {
    const std::string msg = load_error(replace(kPlanar, "{name: A,", "{name: O,"));
    EXPECT_CONTAINS(msg, at_line(16));
    EXPECT_CONTAINS(msg, "duplicate joint name 'O'");
}

TEST(SceneErrors, WrongVectorLength) {
    const std::string msg = load_error(replace(kPlanar, "position: [0.3, 0]", "position: [0.3, 0, 0]"));
    EXPECT_CONTAINS(msg, at_line(12));
    EXPECT_CONTAINS(msg, "body 'rod'");
    EXPECT_CONTAINS(msg, "'position' must have 2 numbers");
}

TEST(SceneErrors, MissingDimension) {
    const std::string msg = load_error(replace(kPlanar, "dimension: planar\n", ""));
    EXPECT_CONTAINS(msg, "'dimension'");
}

TEST(SceneErrors, BadDimension) {
    const std::string msg = load_error(replace(kPlanar, "dimension: planar", "dimension: 2d"));
    EXPECT_CONTAINS(msg, at_line(2));
    EXPECT_CONTAINS(msg, "'planar' or 'spatial'");
}

TEST(SceneErrors, DriverOnJointWithoutCoordinate) {
    const std::string msg = load_error(R"(dimension: spatial
bodies:
  - {name: bob, mass: 1, inertia: [1, 1, 1], position: [0, 0, -1]}
joints:
  - {name: ball, type: spherical, bodies: [ground, bob], point: [0, 0, 0]}
drivers:
  - name: spin
    joint: ball
    motion: {type: linear, initial: 0, rate: 1}
)");
    EXPECT_CONTAINS(msg, at_line(8));
    EXPECT_CONTAINS(msg, "joint 'ball' (spherical) has no single coordinate to drive");
}

TEST(SceneErrors, DriverOnUndefinedJoint) {
    const std::string msg = load_error(replace(kPlanar, "joint: O,", "joint: Q,"));
    EXPECT_CONTAINS(msg, at_line(18));
    EXPECT_CONTAINS(msg, "undefined joint 'Q'");
    EXPECT_CONTAINS(msg, "'O', 'A'");
}

TEST(SceneErrors, UnknownDriverKey) {
    const std::string msg = load_error(replace(kPlanar, "motion: {", "moton: {"));
    EXPECT_CONTAINS(msg, at_line(18));
    EXPECT_CONTAINS(msg, "did you mean 'motion'?");
}

TEST(SceneErrors, GravityIsNotAForce) {
    const std::string msg = load_error(kPlanar + "forces:\n  - {type: gravity, body: rod}\n");
    EXPECT_CONTAINS(msg, at_line(20));
    EXPECT_CONTAINS(msg, "top-level 'gravity");
}

TEST(SceneErrors, DuplicateKey) {
    const std::string msg = load_error(replace(kPlanar, "    angle: 0\n  - name: rod", "    angle: 0\n    mass: 2\n  - name: rod"));
    EXPECT_CONTAINS(msg, at_line(9));
    EXPECT_CONTAINS(msg, "duplicate key 'mass'");
}

TEST(SceneErrors, ZeroEulerParameters) {
    const std::string msg = load_error(R"(dimension: spatial
bodies:
  - name: box
    mass: 1
    inertia: [1, 1, 1]
    orientation: {euler_parameters: [0, 0, 0, 0]}
)");
    EXPECT_CONTAINS(msg, at_line(6));
    EXPECT_CONTAINS(msg, "body 'box'");
    EXPECT_CONTAINS(msg, "zero");
}

// ---------------------------------------------------------------- good scenes

namespace {

// World frame of marker k of a joint at the model's initial state.
struct WorldMarker {
    mbd::Vec3 origin;
    mbd::Mat3 axes;
};

WorldMarker world_marker(const mbd::Model& model, int body, const mbd::Marker& m) {
    mbd::Vec3 R = mbd::Vec3::Zero();
    mbd::Mat3 A = mbd::Mat3::Identity();
    if (body != mbd::kGround) {
        const mbd::Body& b = model.bodies[body];
        R = b.position;
        if (model.dimension == mbd::Dimension::Planar) {
            A.topLeftCorner<2, 2>() = mbd::planar_rotation(b.angle);
        } else {
            A = mbd::rotation_from_euler_parameters(b.euler_parameters);
        }
    }
    WorldMarker w;
    w.origin = R + A * m.u_bar;
    w.axes = A * m.A_bar;
    if (model.dimension == mbd::Dimension::Planar) {
        const double angle = (body == mbd::kGround ? 0.0 : model.bodies[body].angle) + m.angle;
        w.axes = mbd::Mat3::Identity();
        w.axes.topLeftCorner<2, 2>() = mbd::planar_rotation(angle);
    }
    return w;
}

void expect_markers_coincide(const mbd::Model& model) {
    for (const auto& joint : model.joints) {
        SCOPED_TRACE("joint '" + joint.name + "'");
        ASSERT_EQ(joint.bodies.size(), joint.markers.size());
        const WorldMarker first = world_marker(model, joint.bodies[0], joint.markers[0]);
        EXPECT_LT((first.axes.transpose() * first.axes - mbd::Mat3::Identity()).norm(), 1e-12);
        for (size_t k = 1; k < joint.bodies.size(); ++k) {
            const WorldMarker other = world_marker(model, joint.bodies[k], joint.markers[k]);
            EXPECT_LT((other.origin - first.origin).norm(), 1e-12);
            EXPECT_LT((other.axes - first.axes).norm(), 1e-12);
        }
    }
}

}  // namespace

TEST(SceneLoad, PlanarSceneLoads) {
    const mbd::Model model = mbd::load_scene_text(kPlanar, kLabel, registry());
    EXPECT_EQ(model.name, "slider-crank");
    EXPECT_EQ(model.source, kLabel);
    EXPECT_EQ(model.dimension, mbd::Dimension::Planar);
    ASSERT_EQ(model.body_count(), 2);
    EXPECT_EQ(model.bodies[1].name, "rod");
    EXPECT_DOUBLE_EQ(model.bodies[1].inertia(2, 2), 0.05);
    EXPECT_EQ(model.bodies[0].where, at_line(4));
    ASSERT_EQ(model.joints.size(), 2u);
    EXPECT_EQ(model.joints[0].bodies, (std::vector<int>{mbd::kGround, 0}));
    EXPECT_EQ(model.joints[1].bodies, (std::vector<int>{0, 1}));
    EXPECT_TRUE(model.joints[0].joint->has_coordinate());
    // A on the crank at +0.1 along its x axis, on the rod at -0.1
    EXPECT_NEAR(model.joints[1].markers[0].u_bar.x(), 0.1, 1e-15);
    EXPECT_NEAR(model.joints[1].markers[1].u_bar.x(), -0.1, 1e-15);
    ASSERT_EQ(model.drivers.size(), 1u);
    EXPECT_EQ(model.drivers[0].name, "motor");
    EXPECT_EQ(model.drivers[0].joint, 0);
    EXPECT_TRUE(model.forces.empty());  // zero gravity: no gravity force
    expect_markers_coincide(model);
}

TEST(SceneLoad, RotatedPlanarBodiesAndAxis) {
    const mbd::Model model = mbd::load_scene_text(R"(dimension: planar
bodies:
  - {name: a, mass: 1, inertia: 1, position: [1, 2], angle: 0.7}
  - {name: b, mass: 1, inertia: 1, position: [2, 1], angle: -2.1}
joints:
  - {name: slide, type: prismatic, bodies: [a, b], point: [1.5, 1.2], axis: [1, 1]}
)",
                                                  kLabel, registry());
    expect_markers_coincide(model);
    // marker x axis on a: world 45 degrees minus the body's 0.7
    EXPECT_NEAR(model.joints[0].markers[0].angle, M_PI / 4 - 0.7, 1e-14);
    EXPECT_NEAR(model.joints[0].markers[1].angle, M_PI / 4 + 2.1, 1e-14);
}

TEST(SceneLoad, SpatialSceneLoads) {
    const mbd::Model model = mbd::load_scene_text(R"(name: arm
dimension: spatial
bodies:
  - name: upper
    mass: 2
    inertia: [[0.1, 0.01, 0], [0.01, 0.2, 0], [0, 0, 0.3]]
    position: [0.2, 0.1, 0.3]
    orientation: {axis: [1, 2, 3], angle: 0.8}
  - name: lower
    mass: 1
    inertia: [0.1, 0.1, 0.05]
    position: [0.5, -0.2, 0.1]
    orientation: {euler_parameters: [2, 0.2, -0.4, 0.6]}
  - name: hand
    mass: 1
    inertia: [0.1, 0.1, 0.05]
    position: [0.8, -0.2, 0.1]
    orientation: {matrix: [[0, -1, 0], [1, 0, 0], [0, 0, 1]]}
joints:
  - {name: shoulder, type: spherical, bodies: [ground, upper], point: [0, 0, 0.5]}
  - {name: elbow, type: revolute, bodies: [upper, lower], point: [0.4, 0, 0.2], axis: [0, 1, 1], x_axis: [1, 0, 0]}
  - {name: wrist, type: universal, bodies: [lower, hand], point: [0.7, -0.2, 0.1], axes: [[0, 0, 2], [0, 3, 0]]}
)",
                                                  kLabel, registry());
    ASSERT_EQ(model.body_count(), 3);
    EXPECT_NEAR(model.bodies[1].euler_parameters.norm(), 1.0, 1e-15);
    EXPECT_DOUBLE_EQ(model.bodies[0].inertia(0, 1), 0.01);
    ASSERT_EQ(model.joints.size(), 3u);
    expect_markers_coincide(model);
    // elbow frame: z along (0, 1, 1)/sqrt 2, x along world x
    const WorldMarker elbow = world_marker(model, 0, model.joints[1].markers[0]);
    EXPECT_LT((elbow.axes.col(2) - mbd::Vec3(0, 1, 1).normalized()).norm(), 1e-12);
    EXPECT_LT((elbow.axes.col(0) - mbd::Vec3::UnitX()).norm(), 1e-12);
    // universal: z = a1, x = a2
    const WorldMarker wrist = world_marker(model, 1, model.joints[2].markers[0]);
    EXPECT_LT((wrist.axes.col(2) - mbd::Vec3::UnitZ()).norm(), 1e-12);
    EXPECT_LT((wrist.axes.col(0) - mbd::Vec3::UnitY()).norm(), 1e-12);
    EXPECT_EQ(model.name, "arm");
}

TEST(SceneLoad, DefaultJointPointIsFirstMovingBodyCentre) {
    const mbd::Model model = mbd::load_scene_text(R"(dimension: planar
bodies:
  - {name: a, mass: 1, inertia: 1, position: [1, 2], angle: 0.3}
joints:
  - {name: pin, type: revolute, bodies: [ground, a]}
)",
                                                  kLabel, registry());
    EXPECT_LT((model.joints[0].markers[0].u_bar.head<2>() - mbd::Vec2(1, 2)).norm(), 1e-15);
    EXPECT_LT(model.joints[0].markers[1].u_bar.norm(), 1e-15);
    expect_markers_coincide(model);
}

TEST(SceneLoad, ExampleScenesLoad) {
    const std::filesystem::path scenes = std::filesystem::path(MBD_SOURCE_DIR) / "scenes";
    std::vector<std::filesystem::path> files{scenes / "four-bar.yaml"};
    for (const auto& entry : std::filesystem::directory_iterator(scenes / "examples"))
        if (entry.path().extension() == ".yaml") files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    EXPECT_GE(files.size(), 20u);
    for (const auto& file : files) {
        SCOPED_TRACE(file.string());
        try {
            const mbd::Model model = mbd::load_scene(file, registry());
            EXPECT_GT(model.body_count(), 0);
            expect_markers_coincide(model);
        } catch (const std::exception& e) {
            ADD_FAILURE() << e.what();
        }
    }
}

TEST(SceneLoad, FourBar) {
    const mbd::Model model =
        mbd::load_scene(std::filesystem::path(MBD_SOURCE_DIR) / "scenes/four-bar.yaml", registry());
    ASSERT_EQ(model.body_count(), 3);
    ASSERT_EQ(model.joints.size(), 4u);
    ASSERT_EQ(model.drivers.size(), 1u);
    // gravity first, then the spring
    ASSERT_EQ(model.forces.size(), 2u);
    EXPECT_EQ(model.forces[0].type, "gravity");
    EXPECT_EQ(model.forces[0].bodies, (std::vector<int>{0, 1, 2}));
    EXPECT_EQ(model.forces[1].name, "spring");
    EXPECT_NEAR(model.forces[1].markers[0].u_bar.x(), 0.03, 1e-15);
    EXPECT_NEAR(model.forces[1].markers[1].u_bar.x(), -0.05, 1e-15);
    // the link ends meet: every joint's markers coincide at t = 0 to the scene's precision
    for (const auto& joint : model.joints) {
        SCOPED_TRACE(joint.name);
        const WorldMarker a = world_marker(model, joint.bodies[0], joint.markers[0]);
        const WorldMarker b = world_marker(model, joint.bodies[1], joint.markers[1]);
        EXPECT_LT((a.origin - b.origin).norm(), 1e-12);
        // joint points sit on the link ends: |u_bar| = half the link length
        for (size_t k = 0; k < 2; ++k)
            if (joint.bodies[k] != mbd::kGround) {
                const double half[] = {0.1, 0.2, 0.25};
                EXPECT_NEAR(joint.markers[k].u_bar.norm(), half[joint.bodies[k]], 1e-9);
                EXPECT_NEAR(joint.markers[k].u_bar.y(), 0.0, 1e-9);  // on the link's x axis
            }
    }
}

namespace {

// `base: FILE`: a scene derived from another one inherits its top-level keys, replaces the
// ones it gives, is named after its own file, and errors keep pointing at the right file.
class SceneBase : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = std::filesystem::temp_directory_path() / ("mbd-base-" + std::to_string(::getpid()));
        std::filesystem::create_directories(dir_ / "sub");
        write("sub/base.yaml", kPlanar);
    }
    void TearDown() override { std::filesystem::remove_all(dir_); }
    std::filesystem::path write(const std::string& name, const std::string& text) {
        std::ofstream(dir_ / name) << text;
        return dir_ / name;
    }
    std::string error_of(const std::filesystem::path& file) {
        try {
            mbd::load_scene(file, registry());
        } catch (const mbd::InputError& e) {
            return e.what();
        }
        ADD_FAILURE() << "expected an InputError";
        return {};
    }
    std::filesystem::path dir_;
};

TEST_F(SceneBase, InheritsAndOverridesTopLevelKeys) {
    const auto file = write("derived.yaml", "base: sub/base.yaml\ngravity: [0, -9.81]\n");
    const mbd::Model model = mbd::load_scene(file, registry());
    EXPECT_EQ(model.name, "derived");
    ASSERT_EQ(model.bodies.size(), 2u);
    EXPECT_EQ(model.bodies[1].name, "rod");
    EXPECT_DOUBLE_EQ(model.gravity.y(), -9.81);
    const auto replaced = write("replaced.yaml", "base: sub/base.yaml\nbodies:\n  - {name: crank, mass: 3, inertia: 1}\n"
                                                 "  - {name: rod, mass: 1, inertia: 1, position: [0.3, 0]}\n");
    EXPECT_DOUBLE_EQ(mbd::load_scene(replaced, registry()).bodies[0].mass, 3.0);
}

TEST_F(SceneBase, MissingBaseAndErrorsInsideTheBaseNameTheirFile) {
    const std::string missing = error_of(write("missing.yaml", "name: m\nbase: nowhere.yaml\n"));
    EXPECT_CONTAINS(missing, "missing.yaml:2");
    EXPECT_CONTAINS(missing, "nowhere.yaml");
    write("sub/bad.yaml", replace(kPlanar, "    mass: 1\n    inertia: 0.05", "    mass: -1\n    inertia: 0.05"));
    const std::string inside = error_of(write("uses-bad.yaml", "base: sub/bad.yaml\n"));
    EXPECT_CONTAINS(inside, "bad.yaml:10");
    EXPECT_CONTAINS(inside, "body 'rod'");
    // a misspelt key of the base is at its line in the base file, not in the scene that uses it
    write("sub/typo.yaml", replace(kPlanar, "    inertia: 0.05", "    inertia: 0.05\n    masss: 1"));
    const std::string typo = error_of(write("uses-typo.yaml", "name: typo\nbase: sub/typo.yaml\n"));
    EXPECT_CONTAINS(typo, "typo.yaml:12: unknown key 'masss'");
    EXPECT_EQ(typo.find("uses-typo.yaml"), std::string::npos) << typo;
    const std::string cycle = error_of(write("loop.yaml", "base: loop.yaml\n"));
    EXPECT_CONTAINS(cycle, "cycle");
    // found by the fuzzer (scripts/fuzz.sh): a name too long for the file system is bad input too
    const std::string too_long = error_of(write("long.yaml", "base: " + std::string(5000, 'x') + "\n"));
    EXPECT_CONTAINS(too_long, "long.yaml:1");
    EXPECT_CONTAINS(too_long, "cannot read the base scene");
    EXPECT_CONTAINS(error_of(write("dir.yaml", "base: sub\n")), "it is a directory");
}

}  // namespace
