// Issue 37, URDF <visual> shapes as the scene's `visual:` (import/src/urdf_reader.cpp add_visual,
// scene_writer.cpp write_visuals; docs/import.md): primitives and STL/OBJ meshes posed in the body
// frame (origin the mass centre, the link's axes), a missing mesh a warning naming the file and the
// link, and the dynamics unchanged by any of it.
#include "support/mujoco_oracle.hpp"
#include "support/input_files.hpp"
#include "support/test_support.hpp"

#include <mbd/import/import.hpp>
#include <mbd/import/scene_writer.hpp>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <fstream>
#include <regex>

namespace mbd::test {
namespace {

namespace fs = std::filesystem;

fs::path write_file(const std::string& name, const std::string& content) {
    return write_scratch_file("import_visuals", name, content);
}

// A pendulum link whose frame sits at the hinge (z = 1, turned 90 degrees about x) and whose mass
// centre lies 0.2 m along its own -z: a box 0.1 m along the link's x turned 90 degrees about its z,
// a cylinder, a sphere, the tetrahedron of scenes/examples as a mesh, and a mesh that is missing.
std::string urdf() {
    const std::string mesh = (source_dir() / "scenes/examples/meshes/tetrahedron.stl").string();
    return R"(<?xml version="1.0"?>
<robot name="drawn">
  <link name="base"/>
  <link name="arm">
    <inertial><mass value="1"/><origin xyz="0 0 -0.2"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.002"/></inertial>
    <visual><origin xyz="0.1 0 0" rpy="0 0 1.5707963267948966"/><geometry><box size="0.1 0.2 0.3"/></geometry>
      <material name="blue"><color rgba="0.1 0.2 0.8 1"/></material></visual>
    <visual><origin xyz="0 0 -0.2"/><geometry><cylinder radius="0.02" length="0.4"/></geometry></visual>
    <visual><origin xyz="0 0 -0.4"/><geometry><sphere radius="0.05"/></geometry></visual>
    <visual><geometry><mesh filename="file://)" + mesh + R"(" scale="0.1 0.1 0.1"/></geometry></visual>
    <visual><geometry><mesh filename="package://nowhere/meshes/arm.stl"/></geometry></visual>
  </link>
  <joint name="hinge" type="continuous"><parent link="base"/><child link="arm"/><origin xyz="0 0 1" rpy="1.5707963267948966 0 0"/>
    <axis xyz="1 0 0"/></joint>
</robot>
)";
}

TEST(ImportVisuals, UrdfShapesArePosedInTheBodyFrame) {
    const fs::path file = write_file("drawn.urdf", urdf());
    const import::ImportedScene scene = import::import_model(file);
    const std::string missing = import::unmapped_summary(scene.unmapped);
    EXPECT_NE(missing.find("1 visual meshes not found (package://nowhere/meshes/arm.stl (link 'arm'))"), std::string::npos) << missing;
    const Model model = load_scene_text(import::scene_yaml(scene), "drawn.yaml", shared_registry());
    const std::vector<VisualShape>& shapes = model.bodies.at(model.body_index("arm")).visuals;
    ASSERT_EQ(shapes.size(), 4u);  // the missing mesh is not drawn
    // body frame: origin the mass centre, 0.2 m along the link's -z; axes the link's
    EXPECT_EQ(shapes[0].kind, ShapeKind::Box);
    EXPECT_LT((shapes[0].position - Vec3(0.1, 0, 0.2)).norm(), 1e-12);
    EXPECT_LT((shapes[0].rotation - Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ()).toRotationMatrix()).norm(), 1e-12);
    EXPECT_LT((shapes[0].size - Vec3(0.1, 0.2, 0.3)).norm(), 1e-15);
    EXPECT_LT((shapes[0].color - Vec3(0.1, 0.2, 0.8)).norm(), 1e-7);  // urdfdom keeps colours as floats
    EXPECT_EQ(shapes[1].kind, ShapeKind::Cylinder);
    EXPECT_LT(shapes[1].position.norm(), 1e-12);
    EXPECT_EQ(shapes[1].length, 0.4);
    EXPECT_EQ(shapes[2].kind, ShapeKind::Sphere);
    EXPECT_LT((shapes[2].position - Vec3(0, 0, -0.2)).norm(), 1e-12);
    EXPECT_EQ(shapes[3].kind, ShapeKind::Mesh);
    EXPECT_LT((shapes[3].scale - Vec3::Constant(0.1)).norm(), 1e-15);
    EXPECT_TRUE(fs::equivalent(shapes[3].mesh_file, source_dir() / "scenes/examples/meshes/tetrahedron.stl"));
}

// The same link without its <visual> elements moves exactly as with them (bit for bit), and the
// command imports the file with its one warning naming the missing mesh (exit 0).
TEST(ImportVisuals, VisualsAndMissingMeshesLeaveTheDynamicsAlone) {
    const fs::path drawn = write_file("drawn.urdf", urdf());
    const fs::path bare = write_file("bare.urdf", std::regex_replace(urdf(), std::regex("<visual>[\\s\\S]*?</visual>"), ""));
    import::ImportOptions options;
    options.joint_velocities["hinge"] = {2.0};
    auto run = [&](const fs::path& file) {
        return mbd_run(load_scene_text(import::scene_yaml(import::import_model(file, options)), file.string(), shared_registry()),
                       0.5, 0.01);
    };
    const std::vector<Eigen::VectorXd> a = run(drawn), b = run(bare);
    ASSERT_EQ(a.size(), b.size());
    for (size_t s = 0; s < a.size(); ++s) EXPECT_EQ((a[s] - b[s]).cwiseAbs().maxCoeff(), 0.0) << s;
    EXPECT_GT((a.back() - a.front()).norm(), 0.1);  // it did move
    const CommandResult r = run_mbd("import " + drawn.string() + " -o " + (scratch("import_visuals_cli") / "s.yaml").string());
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("visual meshes not found (package://nowhere/meshes/arm.stl (link 'arm'))"), std::string::npos) << r.err;
}

// MJCF geoms (sizes are half sizes in MuJoCo): a box turned 90 degrees about its z, a capsule given
// by fromto along the link, an ellipsoid (no mbd shape: not drawn), posed in the body frame.
TEST(ImportVisuals, MjcfGeomsArePosedInTheBodyFrame) {
    const fs::path file = write_file("drawn.xml", R"(<mujoco model="drawn">
  <worldbody><geom name="floor" type="plane" size="1 1 0.1"/>
    <body name="arm" pos="0 0 1">
      <joint name="hinge" type="hinge" axis="1 0 0"/>
      <inertial pos="0 0 -0.2" mass="1" diaginertia="0.01 0.01 0.002"/>
      <geom name="plate" type="box" size="0.05 0.1 0.15" pos="0.1 0 0" euler="0 0 90" rgba="0.1 0.2 0.8 1"/>
      <geom name="rod" type="capsule" fromto="0 0 0 0 0 -0.4" size="0.02"/>
      <geom name="blob" type="ellipsoid" size="0.03 0.04 0.05" pos="0 0 -0.4"/>
    </body>
  </worldbody>
</mujoco>
)");
    const import::ImportedScene scene = import::import_model(file);
    const Model model = load_scene_text(import::scene_yaml(scene), "drawn.yaml", shared_registry());
    const std::vector<VisualShape>& shapes = model.bodies.at(model.body_index("arm")).visuals;
    ASSERT_EQ(shapes.size(), 2u);
    EXPECT_EQ(shapes[0].kind, ShapeKind::Box);
    EXPECT_LT((shapes[0].size - Vec3(0.1, 0.2, 0.3)).norm(), 1e-12);
    EXPECT_LT((shapes[0].position - Vec3(0.1, 0, 0.2)).norm(), 1e-12);
    EXPECT_LT((shapes[0].rotation - Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ()).toRotationMatrix()).norm(), 1e-9);
    EXPECT_LT((shapes[0].color - Vec3(0.1, 0.2, 0.8)).norm(), 1e-7);  // MuJoCo keeps colours as floats
    EXPECT_EQ(shapes[1].kind, ShapeKind::Capsule);
    EXPECT_LT(shapes[1].position.norm(), 1e-12);  // the rod's centre is the mass centre
    EXPECT_NEAR(shapes[1].length, 0.4, 1e-12);
    EXPECT_NEAR(shapes[1].radius, 0.02, 1e-15);
    EXPECT_NEAR(std::abs(shapes[1].rotation.col(2).z()), 1.0, 1e-12);  // along the link
}

// SDF <visual>: a box posed relative to its link (libsdformat resolves the pose), a missing mesh named.
TEST(ImportVisuals, SdfVisualsArePosedInTheBodyFrame) {
    const fs::path file = write_file("drawn.sdf", R"(<?xml version="1.0"?>
<sdf version="1.9"><model name="drawn">
  <link name="arm"><pose>0 0 1 0 0 0</pose>
    <inertial><pose>0 0 -0.2 0 0 0</pose><mass>1</mass>
      <inertia><ixx>0.01</ixx><iyy>0.01</iyy><izz>0.002</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia></inertial>
    <visual name="plate"><pose>0.1 0 0 0 0 1.5707963267948966</pose><geometry><box><size>0.1 0.2 0.3</size></box></geometry>
      <material><diffuse>0.1 0.2 0.8 1</diffuse></material></visual>
    <visual name="shell"><geometry><mesh><uri>model://nowhere/arm.dae</uri></mesh></geometry></visual>
  </link>
  <joint name="hinge" type="revolute"><parent>world</parent><child>arm</child><axis><xyz>1 0 0</xyz></axis></joint>
</model></sdf>
)");
    const import::ImportedScene scene = import::import_model(file);
    const std::string missing = import::unmapped_summary(scene.unmapped);
    EXPECT_NE(missing.find("1 visual meshes not found (model://nowhere/arm.dae (link 'arm'))"), std::string::npos) << missing;
    const Model model = load_scene_text(import::scene_yaml(scene), "drawn.yaml", shared_registry());
    const std::vector<VisualShape>& shapes = model.bodies.at(model.body_index("arm")).visuals;
    ASSERT_EQ(shapes.size(), 1u);
    EXPECT_EQ(shapes[0].kind, ShapeKind::Box);
    EXPECT_LT((shapes[0].position - Vec3(0.1, 0, 0.2)).norm(), 1e-12);
    EXPECT_LT((shapes[0].rotation - Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ()).toRotationMatrix()).norm(), 1e-12);
    EXPECT_LT((shapes[0].color - Vec3(0.1, 0.2, 0.8)).norm(), 1e-7);
}

// ../shared/models: the UR5 URDF's meshes are missing on purpose: each is named, the import goes
// on (its dynamics agree with MuJoCo: ImportOracle.Ur5UrdfAgreesWithMuJoCo). The menagerie's MJCF
// models with missing meshes: test_import_missing_meshes.cpp.
TEST(ImportVisuals, SharedModelsWithMissingMeshes) {
    const fs::path out = scratch("import_visuals_shared") / "s.yaml";
    const CommandResult ur5 = run_mbd("import " + (shared_models() / "erd_ur5" / "ur5_robot.urdf").string() + " -o " + out.string());
    EXPECT_EQ(ur5.exit_code, 0) << ur5.err;
    EXPECT_NE(ur5.err.find("7 visual meshes not found (package://example-robot-data/robots/ur_description/meshes/ur5/visual/base.dae "
                           "(link 'base_link')"), std::string::npos) << ur5.err;
}

}  // namespace
}  // namespace mbd::test
