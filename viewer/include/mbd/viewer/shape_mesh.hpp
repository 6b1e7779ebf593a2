// Triangle meshes of the visual shapes (mbd/visual.hpp), shared by the glTF and the HTML
// export: each distinct shape is tessellated once and placed by instances.
#pragma once

#include <mbd/visual.hpp>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace mbd::viewer {

struct TriangleMesh {
    std::vector<float> positions;   // x y z per vertex
    std::vector<float> normals;     // unit, per vertex
    std::vector<uint32_t> indices;  // three per triangle, counter-clockwise seen from outside
    float min[3] = {0, 0, 0}, max[3] = {0, 0, 0};
    void update_bounds();
};

// How finely round shapes are tessellated: vertices around a circle, rings pole to pole.
struct Tessellation {
    int segments = 32;
    int rings = 16;
};

// Coarser the more shapes a scene draws: a 500-link chain at full detail is about 700,000
// triangles, which software WebGL draws at about one frame a second.
Tessellation tessellation_for(size_t shapes);

// The shape in its own frame (no pose or scale): box centred, sphere, cylinder and capsule
// along z centred on the origin, a mesh file as written (read with Assimp; a file it cannot
// read throws InputError naming the file and the visual's file:line).
TriangleMesh shape_mesh(const VisualShape& shape, Tessellation detail = {});

// A shape placed on a body (or the ground): mesh index, pose in the body frame, colour.
struct ShapeInstance {
    int mesh = 0;
    Vec3 position = Vec3::Zero();
    Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
    Vec3 scale = Vec3::Ones();
    Vec3 color = Vec3::Ones();
};

struct SceneMeshes {
    std::vector<TriangleMesh> meshes;
    std::vector<std::vector<ShapeInstance>> bodies;
    std::vector<ShapeInstance> ground;
    int connector_mesh = -1;  // a unit cylinder from z = 0 to z = 1, radius 1
};

SceneMeshes scene_meshes(const VisualScene& scene);

}  // namespace mbd::viewer
