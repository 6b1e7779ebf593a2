// What a body looks like: the `visual:` key of a body (docs/scene-format.md) and,
// for bodies without it, shapes derived from the scene (links between the joint
// points, a sphere at the mass centre, joint axes, springs, a ground grid).
// Geometry only: nothing here renders; viewer/ turns it into glTF and HTML.
#pragma once

#include <mbd/sdk/body_state.hpp>
#include <mbd/sdk/params.hpp>

#include <Eigen/Geometry>

#include <filesystem>
#include <string>
#include <vector>

namespace mbd {

class Model;

enum class ShapeKind { Box, Cylinder, Sphere, Capsule, Mesh };

const char* shape_kind_name(ShapeKind kind);

// One shape, posed in its body's frame (origin at the mass centre, body axes).
// Cylinders and capsules run along the shape's own z axis, centred on its origin.
struct VisualShape {
    ShapeKind kind = ShapeKind::Sphere;
    Vec3 size = Vec3::Ones();   // box: edge lengths along x, y, z
    double radius = 0.0;        // sphere, cylinder, capsule
    double length = 0.0;        // cylinder: height; capsule: distance between the cap centres
    std::string mesh_file;      // mesh: path resolved against the scene file's folder
    Vec3 position = Vec3::Zero();
    Mat3 rotation = Mat3::Identity();
    Vec3 scale = Vec3::Ones();
    Vec3 color = Vec3(0.62, 0.64, 0.68);  // linear RGB in [0, 1]
    std::string where;          // file:line of its definition ("" when derived)
};

// Reads a body's `visual:` value (one map or a list of maps). Throws InputError at the
// offending key's file:line; a mesh file must exist. `what` names the body.
std::vector<VisualShape> parse_visual(const Param& node, Dimension dimension, const std::string& what);

// A line drawn between two attachment points of a two-body force (a spring, a damper).
struct VisualConnector {
    std::string name;
    int body_a = -1, body_b = -1;  // body indices, kGround for the ground
    Vec3 point_a = Vec3::Zero(), point_b = Vec3::Zero();  // in each body's frame
    double radius = 0.0;
    Vec3 color = Vec3(0.85, 0.55, 0.15);
};

// Everything drawn: shapes moving with each body, shapes fixed to the ground, connectors
// that follow two bodies, and a grid on the ground plane.
struct VisualScene {
    std::vector<std::vector<VisualShape>> bodies;  // one list per body, in Model::bodies order
    std::vector<VisualShape> ground;               // world frame
    std::vector<VisualConnector> connectors;
    Vec3 up = Vec3::UnitY();       // opposite to gravity (planar default y, spatial default z)
    double length_scale = 1.0;     // typical size of a link, for default sizes
    Vec3 grid_centre = Vec3::Zero();
    Vec3 grid_normal = Vec3::UnitZ();  // the grid lies across this direction
    double grid_size = 1.0;        // edge length of the square grid
    int grid_divisions = 10;
};

// The shapes of every body: its `visual:` shapes, or derived ones when it has none.
VisualScene build_visual_scene(const Model& model);

// Resizes the ground grid to cover `extent` (world), e.g. every mass centre of a motion.
void fit_ground_grid(const Model& model, VisualScene& scene, const Eigen::AlignedBox3d& extent);

}  // namespace mbd
