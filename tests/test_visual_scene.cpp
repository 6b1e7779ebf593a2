// Issue 41, shapes derived from the scene against the mechanism's own scale: chain-50's links
// are thick against the whole chain (in the scene and in the .glb); wheels of rolling contacts
// are discs of their contact radius (the Whipple benchmark's 0.3 and 0.35 m, the wheelset's
// 0.45 m tape circle); a spinning symmetric rotor is the disc of its axial moment with a bar
// across its face; markers of rolling contacts ride on the wheel, not on the ground.
// The browser's view of the same scenes: viewer/test/mechanisms.mjs (ctest viewer_browser_mechanisms).
#include <mbd/model.hpp>
#include <mbd/visual.hpp>
#include <mbd/visual_joint_markers.hpp>

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <cmath>

#include "support/test_support.hpp"

namespace {

namespace fs = std::filesystem;
using mbd::ShapeKind;
using mbd::Vec3;
using mbd::VisualShape;

int body_index(const mbd::Model& model, const std::string& name) {
    for (int b = 0; b < model.body_count(); ++b)
        if (model.bodies[b].name == name) return b;
    ADD_FAILURE() << "no body " << name;
    return 0;
}

std::vector<const VisualShape*> shapes_of(const std::vector<VisualShape>& shapes, ShapeKind kind) {
    std::vector<const VisualShape*> out;
    for (const auto& s : shapes)
        if (s.kind == kind) out.push_back(&s);
    return out;
}

// The disc of `radius` about `axis` (body frame) centred at `centre` among the shapes, or null.
const VisualShape* disc(const std::vector<VisualShape>& shapes, double radius, const Vec3& axis, const Vec3& centre) {
    for (const VisualShape* s : shapes_of(shapes, ShapeKind::Cylinder))
        if (std::abs(s->radius - radius) < 1e-12 && s->length < 0.3 * radius &&
            std::abs(std::abs((s->rotation * Vec3::UnitZ()).dot(axis.normalized())) - 1.0) < 1e-12 &&
            (s->position - centre).norm() < 1e-9)
            return s;
    return nullptr;
}

// chain-50: 50 links of 0.1 m along x from the origin, a chain 5 m long; its joint points and mass
// centres span x = 0 .. 4.95 (the free tip is neither). Links 4 % of their own length thick
// (0.004 m) are under a pixel at a camera that frames 5 m; drawn at least 0.5 % of that extent
// (0.02475 m), each is a few pixels thick. The last link has one joint point: its link runs from
// there to its mass centre (0.05 m).
TEST(VisualScale, ChainLinksAreThickAgainstTheWholeChain) {
    const mbd::Model model = mbd::test::load("bench/chain-50.yaml");
    const mbd::VisualScene scene = mbd::build_visual_scene(model);
    const double extent = 4.95, least = 0.005 * extent;
    for (int b = 0; b < model.body_count(); ++b) {
        const VisualShape* link = nullptr;
        for (const VisualShape* s : shapes_of(scene.bodies[b], ShapeKind::Cylinder))
            if (std::abs(s->length - (b + 1 < model.body_count() ? 0.1 : 0.05)) < 1e-9) link = s;
        ASSERT_NE(link, nullptr) << model.bodies[b].name;
        EXPECT_GE(link->radius, least - 1e-12) << model.bodies[b].name;
    }
    // the .glb carries the same link: the cylinder mesh of a body node is 2 r wide
    const fs::path dir = mbd::test::scratch("visual-scale-chain");
    const auto run = mbd::test::run_mbd("simulate '" + mbd::test::scene_path("bench/chain-50.yaml").string() +
                                        "' --t-end 0.01 --output-step 0.01 -q --output '" + (dir / "r.csv").string() +
                                        "' --animation '" + (dir / "r.glb").string() + "'");
    ASSERT_EQ(run.exit_code, 0) << run.err;
    tinygltf::Model glb;
    tinygltf::TinyGLTF loader;
    std::string error, warning;
    ASSERT_TRUE(loader.LoadBinaryFromFile(&glb, &error, &warning, (dir / "r.glb").string())) << error;
    double link_width = 0.0;
    for (const auto& node : glb.nodes) {
        if (node.name.rfind("l7/shape", 0) != 0 || node.mesh < 0) continue;
        const auto& a = glb.accessors[glb.meshes[node.mesh].primitives[0].attributes.at("POSITION")];
        const double length = a.maxValues[2] - a.minValues[2], width = a.maxValues[0] - a.minValues[0];
        if (std::abs(length - 0.1) < 1e-6) link_width = width;
    }
    EXPECT_GE(link_width, 2.0 * least - 1e-6);
}

// The Whipple bicycle (Meijaard et al. 2007, Table 1): wheel radii 0.3 m (rear) and 0.35 m
// (front), hubs about body y. Not the inertia's square plate (0.6 x 0.042 x 0.6 m for the rear).
TEST(VisualScale, WhippleWheelsAreDiscsOfTheirContactRadius) {
    const mbd::Model model = mbd::test::load("reference/whipple-bicycle.yaml");
    std::vector<mbd::JointMarkerShape> markers;
    const mbd::VisualScene scene = mbd::build_visual_scene(model, markers);
    for (const auto& [name, radius] : {std::pair{"rear_wheel", 0.3}, std::pair{"front_wheel", 0.35}}) {
        const auto& shapes = scene.bodies[body_index(model, name)];
        EXPECT_NE(disc(shapes, radius, Vec3::UnitY(), Vec3::Zero()), nullptr) << name;
        for (const VisualShape* box : shapes_of(shapes, ShapeKind::Box)) {
            const Vec3 e = box->size;
            EXPECT_LT(e.sum() - e.maxCoeff() - e.minCoeff(), 0.5 * radius) << name << ": a plate, not a bar";
        }
    }
    // the rolling contacts' markers ride on the wheels; the ground holds no marker (no joint
    // holds a body to the ground at a fixed point)
    for (const auto& m : markers) {
        const auto& joint = model.joints[m.joint];
        if (joint.type == "rolling_disc") EXPECT_EQ(m.body, joint.bodies[1]) << joint.name;
        EXPECT_NE(m.body, mbd::kGround) << joint.name;
    }
    EXPECT_EQ(markers.size(), model.joints.size());
    EXPECT_TRUE(scene.ground.empty());
}

// The railway wheelset: two conical wheels of tape radius 0.45 m at y = +-0.75 m on the axle (body y).
// The contacts' points on the wheelset are rim points where the wheels touched at t = 0: no link
// joins them (it would turn with the wheels); each contact's marker is the hub of its wheel.
TEST(VisualScale, WheelsetWheelsAtTheirTapeRadius) {
    const mbd::Model model = mbd::test::load("examples/spatial-wheelset.yaml");
    std::vector<mbd::JointMarkerShape> markers;
    const mbd::VisualScene scene = mbd::build_visual_scene(model, markers);
    for (double y : {0.75, -0.75})
        EXPECT_NE(disc(scene.bodies[0], 0.45, Vec3::UnitY(), Vec3(0, y, 0)), nullptr) << "wheel at y = " << y;
    for (const VisualShape* c : shapes_of(scene.bodies[0], ShapeKind::Cylinder))
        EXPECT_NEAR(std::abs(c->position.y()), 0.75, 1e-9) << "a cylinder away from the wheels, at " << c->position.transpose();
    ASSERT_EQ(markers.size(), 2u);
    for (const auto& m : markers) {
        ASSERT_EQ(m.body, 0);
        const VisualShape& hub = scene.bodies[0][m.shape];
        EXPECT_NEAR(std::abs(hub.position.y()), 0.75, 1e-9);
        EXPECT_NEAR(hub.position.x(), 0.0, 1e-9);
        EXPECT_NEAR(hub.position.z(), 0.0, 1e-9);
    }
}

// The gyroscope's top (m = 1, i_xx = i_yy = 0.002, i_zz = 0.004): the thin disc of its axial
// moment, i_zz = m r^2 / 2, r = sqrt(0.008) m, about body z, and a bar across its face
// (perpendicular to the axis), so that the spin shows as the bar turns.
TEST(VisualScale, SpinningRotorIsADiscWithABarAcrossItsFace) {
    const mbd::Model model = mbd::test::load("bench/gyroscope.yaml");
    const mbd::VisualScene scene = mbd::build_visual_scene(model);
    const auto& shapes = scene.bodies[0];
    const VisualShape* rotor = disc(shapes, std::sqrt(0.008), Vec3::UnitZ(), Vec3::Zero());
    ASSERT_NE(rotor, nullptr);
    int bars = 0;
    for (const VisualShape* box : shapes_of(shapes, ShapeKind::Box)) {
        Eigen::Index longest;
        box->size.maxCoeff(&longest);
        const Vec3 along = box->rotation.col(longest);
        if (std::abs(along.dot(Vec3::UnitZ())) < 1e-12 && box->size[longest] > rotor->radius) ++bars;
    }
    EXPECT_EQ(bars, 1);
}

}  // namespace
