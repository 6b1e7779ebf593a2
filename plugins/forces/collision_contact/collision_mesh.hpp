// A collision shape's mesh, read from an STL or OBJ file with Assimp (as `visual:` meshes are):
// its vertices (merged where two triangles give the same position) and triangles, in the shape's
// frame, scaled. A convex mesh must be closed (every edge shared by two triangles, in opposite
// directions) and convex (every vertex on or behind every triangle's plane): FCL's convex
// polytope, and the plugin's vertex contacts against a plane, assume both.
#pragma once

#include <mbd/sdk/params.hpp>
#include <mbd/sdk/rotation.hpp>
#include <mbd/sdk/text.hpp>

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace mbd::collision {

struct Mesh {
    std::vector<Vec3> vertices;
    std::vector<std::array<int, 3>> triangles;  // counter-clockwise seen from outside
};

// The mesh of `file` (relative to the scene file of `at`), scaled along its axes; `owner` names
// the shape in messages, which point at `at`.
std::shared_ptr<const Mesh> read_mesh(const Param& at, const std::string& file, const Vec3& scale,
                                      const std::string& owner);

// Refuses, naming `owner` at `at`, a mesh that is not closed or not convex.
void check_convex(const Mesh& mesh, const Param& at, const std::string& file, const std::string& owner);

}  // namespace mbd::collision
