// Issue 37, visual meshes in Collada (DAE) and glTF: a model's mesh of either format becomes a
// `visual:` mesh that the viewer reads through Assimp as it reads STL and OBJ
// (viewer/src/shape_mesh.cpp; docs/import.md). The files are written by the test, so the oracle
// is what they hold: the vertices as written, a DAE's scaled by its <unit meter> and kept in its
// own axes (ROS's convention, whatever its <up_axis>), a glTF's moved by its node's translation.
#include "support/test_support.hpp"

#include <mbd/import/import.hpp>
#include <mbd/import/scene_writer.hpp>
#include <mbd/viewer/shape_mesh.hpp>

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <array>
#include <cstdint>
#include <fstream>
#include <set>

namespace mbd::test {
namespace {

namespace fs = std::filesystem;

// A tetrahedron's corners and its four outward triangles.
const std::array<std::array<float, 3>, 4> kCorners = {{{0, 0, 0}, {10, 0, 0}, {0, 20, 0}, {0, 0, 30}}};
const std::array<uint16_t, 12> kTriangles = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};

fs::path write_file(const fs::path& path, const std::string& content) {
    std::ofstream(path, std::ios::binary) << content;
    return path;
}

// In centimetres, Z_UP, its node moved 50 cm along z.
std::string collada() {
    std::string positions, triangles;
    for (const auto& c : kCorners)
        for (float x : c) positions += std::to_string(x) + " ";
    for (uint16_t i : kTriangles) triangles += std::to_string(i) + " ";
    return R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="centimeter" meter="0.01"/><up_axis>Z_UP</up_axis></asset>
  <library_geometries><geometry id="tetra"><mesh>
    <source id="corners"><float_array id="xyz" count="12">)" + positions + R"(</float_array>
      <technique_common><accessor source="#xyz" count="4" stride="3">
        <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
      </accessor></technique_common></source>
    <vertices id="v"><input semantic="POSITION" source="#corners"/></vertices>
    <triangles count="4"><input semantic="VERTEX" source="#v" offset="0"/><p>)" + triangles + R"(</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="scene"><node id="part"><translate>0 0 50</translate>
    <instance_geometry url="#tetra"/></node></visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
)";
}

// Metres (glTF's unit), the buffer in a .bin beside it, the node moved by (1, 2, 3).
fs::path write_gltf(const fs::path& dir) {
    std::string buffer(reinterpret_cast<const char*>(kCorners.data()), sizeof(kCorners));
    buffer.append(reinterpret_cast<const char*>(kTriangles.data()), sizeof(kTriangles));
    write_file(dir / "tetra.bin", buffer);
    return write_file(dir / "tetra.gltf", R"({
  "asset": {"version": "2.0"},
  "buffers": [{"uri": "tetra.bin", "byteLength": 72}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48, "target": 34962},
                  {"buffer": 0, "byteOffset": 48, "byteLength": 24, "target": 34963}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [10, 20, 30]},
                {"bufferView": 1, "componentType": 5123, "count": 12, "type": "SCALAR"}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
  "nodes": [{"mesh": 0, "translation": [1, 2, 3]}],
  "scenes": [{"nodes": [0]}],
  "scene": 0
})");
}

// The distinct corners the viewer draws, each as the file gives it, scaled and moved.
void expect_the_files_tetrahedron(const viewer::TriangleMesh& mesh, double scale, const Vec3& shift) {
    std::set<std::array<float, 3>> drawn, written;
    for (size_t v = 0; v < mesh.positions.size(); v += 3)
        drawn.insert({mesh.positions[v], mesh.positions[v + 1], mesh.positions[v + 2]});
    for (const auto& c : kCorners)
        written.insert({static_cast<float>(scale * c[0] + shift[0]), static_cast<float>(scale * c[1] + shift[1]),
                        static_cast<float>(scale * c[2] + shift[2])});
    EXPECT_EQ(drawn.size(), 4u);
    EXPECT_EQ(mesh.indices.size(), kTriangles.size());
    for (const auto& w : written) {
        bool found = false;
        for (const auto& d : drawn)
            found = found || (std::abs(d[0] - w[0]) < 1e-6 && std::abs(d[1] - w[1]) < 1e-6 && std::abs(d[2] - w[2]) < 1e-6);
        EXPECT_TRUE(found) << w[0] << " " << w[1] << " " << w[2];
    }
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(mesh.min[k], shift[k], 1e-6) << k;
        EXPECT_NEAR(mesh.max[k], shift[k] + scale * 10.0 * (k + 1), 1e-6) << k;
    }
}

std::string urdf(const fs::path& dae, const fs::path& gltf) {
    return R"(<?xml version="1.0"?>
<robot name="meshes">
  <link name="base"/>
  <link name="arm">
    <inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
    <visual><geometry><mesh filename="file://)" + dae.string() + R"("/></geometry></visual>
    <visual><geometry><mesh filename=")" + gltf.filename().string() + R"("/></geometry></visual>
  </link>
  <joint name="hinge" type="continuous"><parent link="base"/><child link="arm"/><axis xyz="1 0 0"/></joint>
</robot>
)";
}

TEST(ImportMeshFormats, ColladaAndGltfMeshesAreDrawnAsTheFilesHoldThem) {
    const fs::path dir = scratch("import_mesh_formats");
    const fs::path dae = write_file(dir / "tetra.dae", collada());
    const fs::path gltf = write_gltf(dir);
    const fs::path model = write_file(dir / "meshes.urdf", urdf(dae, gltf));
    const import::ImportedScene scene = import::import_model(model);
    EXPECT_EQ(import::unmapped_summary(scene.unmapped), "");  // both drawn, neither listed
    const Model loaded = load_scene_text(import::scene_yaml(scene), (dir / "meshes.yaml").string(), shared_registry());
    const std::vector<VisualShape>& shapes = loaded.bodies.at(loaded.body_index("arm")).visuals;
    ASSERT_EQ(shapes.size(), 2u);
    EXPECT_TRUE(fs::equivalent(shapes[0].mesh_file, dae));
    EXPECT_TRUE(fs::equivalent(shapes[1].mesh_file, gltf));
    // centimetres to metres, kept z up (Assimp's default would turn the Z_UP file to y up)
    expect_the_files_tetrahedron(viewer::shape_mesh(shapes[0]), 0.01, Vec3(0, 0, 0.5));
    expect_the_files_tetrahedron(viewer::shape_mesh(shapes[1]), 1.0, Vec3(1, 2, 3));
}

// The viewer's own export draws them: `simulate --animation` of the model file writes a glTF
// animation holding both meshes (4 corners each, the bounds above); a mesh Assimp cannot read is
// an error naming the file, and nothing is written.
TEST(ImportMeshFormats, TheAnimationHoldsBothMeshesAndABrokenOneIsRefused) {
    const fs::path dir = scratch("import_mesh_formats_animate");
    const fs::path dae = write_file(dir / "tetra.dae", collada());
    const fs::path gltf = write_gltf(dir);
    const fs::path model = write_file(dir / "meshes.urdf", urdf(dae, gltf));
    const CommandResult ok = run_mbd("simulate " + model.string() + " --t-end 0.05 -q -o " + (dir / "a.csv").string() +
                                     " --animation " + (dir / "a.glb").string());
    ASSERT_EQ(ok.exit_code, 0) << ok.err;
    tinygltf::Model glb;
    tinygltf::TinyGLTF loader;
    std::string error, warning;
    ASSERT_TRUE(loader.LoadBinaryFromFile(&glb, &error, &warning, (dir / "a.glb").string())) << error << warning;
    const std::vector<std::vector<double>> bounds = {{0, 0, 0.5, 0.1, 0.2, 0.8}, {1, 2, 3, 11, 22, 33}};
    for (const auto& b : bounds) {
        int found = 0;
        for (const auto& mesh : glb.meshes)
            for (const auto& primitive : mesh.primitives) {
                const tinygltf::Accessor& a = glb.accessors[primitive.attributes.at("POSITION")];
                bool same = a.count == 4 && a.minValues.size() == 3 && a.maxValues.size() == 3;
                for (int k = 0; same && k < 3; ++k)
                    same = std::abs(a.minValues[k] - b[k]) < 1e-6 && std::abs(a.maxValues[k] - b[k + 3]) < 1e-6;
                found += same;
            }
        EXPECT_EQ(found, 1) << "the mesh with bounds from " << b[0] << " " << b[1] << " " << b[2];
    }
    write_file(dae, "<COLLADA>not a mesh");
    const CommandResult bad = run_mbd("simulate " + model.string() + " --t-end 0.05 -q -o " + (dir / "b.csv").string() +
                                      " --animation " + (dir / "b.glb").string());
    EXPECT_EQ(bad.exit_code, 2) << bad.err;
    EXPECT_NE(bad.err.find("tetra.dae"), std::string::npos) << bad.err;
    EXPECT_FALSE(fs::exists(dir / "b.glb"));
}

}  // namespace
}  // namespace mbd::test
