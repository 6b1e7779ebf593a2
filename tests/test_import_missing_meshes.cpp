// Issue 37, MJCF files whose mesh files are missing (import/mjcf_compile, docs/import.md "Missing
// mesh files"): MuJoCo's compiler gets a placeholder through its virtual file system for each file
// it cannot open, each missing file is named in the import's one warning with the geoms drawn from
// it, the placeholder geoms are not drawn, and a body whose inertia MuJoCo would take from a missing
// mesh (no <inertial>: inertiafromgeom) is refused naming the body and the mesh. The dynamics of
// the menagerie models against MuJoCo's own run: ImportOracle.Menagerie* (test_import_oracle.cpp).
#include "support/mujoco_oracle.hpp"
#include "support/input_files.hpp"
#include "support/test_support.hpp"

#include <mbd/import/import.hpp>
#include <mbd/import/scene_writer.hpp>

#include <gtest/gtest.h>

#include <fstream>

namespace mbd::test {
namespace {

namespace fs = std::filesystem;

fs::path write_file(const std::string& name, const std::string& content) {
    return write_scratch_file("import_missing_meshes", name, content);
}

CommandResult import_to(const fs::path& model, const fs::path& out) {
    fs::remove(out);
    return run_mbd("import " + model.string() + " -o " + out.string());
}

// The three menagerie models of ../shared/models import, each missing file named with its asset's
// line and the geoms drawn from it (a mesh reusing a file MuJoCo asked for already: by its name).
TEST(ImportMissingMeshes, MenagerieModelsImportWithTheirMissingMeshesNamed) {
    const fs::path out = scratch("import_missing_meshes") / "menagerie.yaml";
    const fs::path models = shared_models();
    const CommandResult panda = import_to(models / "panda" / "panda.xml", out);
    EXPECT_EQ(panda.exit_code, 0) << panda.err;
    EXPECT_TRUE(fs::exists(out));
    EXPECT_NE(panda.err.find("67 missing mesh and texture files (/"), std::string::npos) << panda.err;
    EXPECT_NE(panda.err.find("/panda/assets/link0.stl (mesh 'link0_c', line 47: geom #11 of body 'link0')"), std::string::npos);
    EXPECT_NE(panda.err.find("/assets/finger_0.obj (mesh 'finger_0', line 114: geom #65 of body 'left_finger', geom #67 of body "
                             "'left_finger', geom #73 of body 'right_finger', geom #75 of body 'right_finger')"), std::string::npos);
    const CommandResult ur5e = import_to(models / "ur5e" / "ur5e.xml", out);
    EXPECT_EQ(ur5e.exit_code, 0) << ur5e.err;
    EXPECT_NE(ur5e.err.find("20 missing mesh and texture files (/"), std::string::npos) << ur5e.err;
    EXPECT_NE(ur5e.err.find("/ur5e/assets/base_0.obj (mesh 'base_0', line 40: geom #0 of body 'base')"), std::string::npos);
    const CommandResult cassie = import_to(models / "cassie" / "cassie.xml", out);
    EXPECT_EQ(cassie.exit_code, 0) << cassie.err;
    EXPECT_NE(cassie.err.find("cassie-texture.png (texture 'cassie', line 26)"), std::string::npos) << cassie.err;
    EXPECT_NE(cassie.err.find("14 missing mesh and texture files (/"), std::string::npos) << cassie.err;
    EXPECT_NE(cassie.err.find("/cassie/assets/pelvis.obj (mesh 'cassie-pelvis', line 28: geom #0 of body 'cassie-pelvis')"),
              std::string::npos);
    EXPECT_NE(cassie.err.find("12 more geoms from missing meshes (mesh 'right-hip-roll' (geom #24 of body 'right-hip-roll')"),
              std::string::npos) << cassie.err;
}

// One hinged body with a sphere, a mesh geom and a box fitted to the same mesh; its inertia given
// by <inertial> unless `inertial` is false (then MuJoCo takes it from the geoms, the missing
// mesh's among them).
std::string arm(bool inertial) {
    return std::string(R"(<mujoco model="arm">
  <asset><mesh name="shell" file="nowhere/shell.stl"/></asset>
  <worldbody>
    <body name="arm" pos="0 0 1">
      )") + (inertial ? R"(<inertial pos="0 0 -0.2" mass="1" diaginertia="0.01 0.01 0.002"/>)" : "") + R"(
      <joint name="hinge" type="hinge" axis="0 1 0"/>
      <geom name="ball" type="sphere" size="0.05" pos="0 0 -0.4"/>
      <geom name="skin" type="mesh" mesh="shell"/>
      <geom name="fitted" type="box" mesh="shell"/>
    </body>
  </worldbody>
</mujoco>
)";
}

// The refusal: exit 2 naming the body, the mesh and the file, nothing written.
TEST(ImportMissingMeshes, BodyWhoseInertiaComesFromAMissingMeshIsRefused) {
    const fs::path out = scratch("import_missing_meshes") / "arm.yaml";
    const CommandResult r = import_to(write_file("arm_from_geoms.xml", arm(false)), out);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("body 'arm' takes its inertia from a mesh that is not there (mesh 'shell'; missing files: "),
              std::string::npos) << r.err;
    EXPECT_NE(r.err.find("nowhere/shell.stl"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("give the body an <inertial> element"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out));
}

// With <inertial> the same body imports: the sphere is drawn, the mesh geom and the box fitted to
// the placeholder are not; the file and both geoms are named; the mass and inertia are the file's.
TEST(ImportMissingMeshes, ExplicitInertiaImportsWithoutThePlaceholderGeoms) {
    const fs::path file = write_file("arm_inertial.xml", arm(true));
    const import::ImportedScene scene = import::import_model(file);
    const std::string warning = import::unmapped_summary(scene.unmapped);
    EXPECT_NE(warning.find("1 missing mesh and texture files (" + (file.parent_path() / "nowhere/shell.stl").string() +
                           " (mesh 'shell', line 2: geom 'skin' of body 'arm'))"), std::string::npos) << warning;
    EXPECT_NE(warning.find("1 more geoms from missing meshes (geom 'fitted' of body 'arm' (fitted to a missing mesh))"),
              std::string::npos) << warning;
    const Model model = load_scene_text(import::scene_yaml(scene), "arm.yaml", shared_registry());
    const Body& body = model.bodies.at(model.body_index("arm"));
    ASSERT_EQ(body.visuals.size(), 1u);
    EXPECT_EQ(body.visuals[0].kind, ShapeKind::Sphere);
    EXPECT_EQ(body.mass, 1.0);
    EXPECT_LT((body.inertia - Vec3(0.01, 0.01, 0.002).asDiagonal().toDenseMatrix()).norm(), 1e-15);
}

}  // namespace
}  // namespace mbd::test
