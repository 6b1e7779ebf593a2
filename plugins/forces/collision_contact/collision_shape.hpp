// One collision shape of a body (or of the ground), as the scene's `collision:` list gives it
// (docs/scene-format.md "Collision shapes"): its kind and sizes, its pose in the body's frame,
// its collision group and mask, and its material.
#pragma once

#include "collision_material.hpp"
#include "collision_mesh.hpp"

#include <mbd/sdk/params.hpp>
#include <mbd/sdk/rotation.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace mbd::collision {

enum class ShapeKind { Sphere, Capsule, Cylinder, Box, Plane, ConvexMesh, TriangleMesh };

struct Shape {
    ShapeKind kind = ShapeKind::Sphere;
    double radius = 0.0;                // sphere, capsule, cylinder
    double length = 0.0;                // capsule: between the cap centres; cylinder: end to end (along z)
    Vec3 size = Vec3::Zero();           // box: the edge lengths along x, y, z
    std::shared_ptr<const Mesh> mesh;   // convex_mesh, triangle_mesh: in the shape's frame, scaled
    Vec3 position = Vec3::Zero();       // the shape's centre (plane: a point on it), body frame
    Mat3 rotation = Mat3::Identity();   // the shape's axes in the body frame (plane: z is the normal)
    int body = 0;                       // the body's position in the element's body list
    std::uint32_t group_bit = 1;        // 1 << group
    std::uint32_t mask = ~0u;           // the groups it collides with, one bit each
    Material material;
    std::string label;                  // "body 'ball', collision shape 1 (sphere)", for messages
    std::string where;                  // file:line of the shape in the scene
};

// The shapes of one body from its `collision:` list. `body` is the body's position in the
// element; `ground` allows planes, triangle meshes and rigid materials; `massless` refuses any
// shape.
std::vector<Shape> read_shapes(const Param& list, const std::string& body_name, int body, bool ground, bool massless);

const char* kind_name(ShapeKind kind);

// The radius of curvature of the shape's surface at a contact (Hertz materials): a sphere's or
// capsule's radius, infinity for the flat faces of boxes and planes.
double curvature_radius(const Shape& s);

}  // namespace mbd::collision
