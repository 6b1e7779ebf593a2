// An imported model as mbd's scene elements (docs/scene-format.md): spatial bodies at their
// mass centres, joints and force elements with world points and axes at t = 0. Built from a
// reader's SourceTree by build_scene (scene_builder.cpp); written as YAML by scene_writer.hpp.
#pragma once

#include <mbd/import/source_tree.hpp>

#include <string>
#include <vector>

namespace mbd::import {

// Mass of the bodies that carry the intermediate frames of a source body with several joints
// (an MJCF body with hinges hip_x, hip_z, hip_y becomes a chain of three mbd joints), as a
// fraction of the model's total mass; their inertia is this mass times (0.1 m)^2. mbd's
// forward dynamics refuses a massless body. With 1e-12 the humanoid moves as in MuJoCo to
// 8.9e-10 over 1 s; 1e-9 had made it differ by 7.3e-7 (docs/import.md, test
// ImportOracle.HumanoidAgreesWithMuJoCo).
constexpr double kFrameMassFraction = 1e-12;

struct SceneBody {
    std::string name;
    std::string where;     // the source element (file, and line where the parser gives it)
    std::string comment;   // what it stands for: "MJCF body 'torso'", "frame after joint 'hip_x' of ..."
    double mass = 0.0;
    Mat3 inertia = Mat3::Zero();       // about the mass centre, body axes
    Vec3 position = Vec3::Zero();      // mass centre, world, t = 0
    Mat3 rotation = Mat3::Identity();  // body axes -> world
    Vec3 velocity = Vec3::Zero();      // of the mass centre, world
    Vec3 angular_velocity = Vec3::Zero();  // world
    bool frame = false;                // an intermediate frame body (kFrameMassFraction)
    std::vector<VisualShape> visuals;  // posed in world at t = 0 (source_tree.hpp)
};

struct SceneJoint {
    std::string name;
    std::string where;
    std::string type;      // revolute, prismatic, spherical, planar, universal, screw, fixed
    int parent = -1;       // index in ImportedScene::bodies, -1: ground
    int child = -1;
    Vec3 point = Vec3::Zero();
    Vec3 axis = Vec3::UnitZ();
    Vec3 axis2 = Vec3::UnitX();  // universal: `axes: [axis, axis2]`
    double pitch = 0.0;          // screw
    std::string comment;         // what it stands for, when not the source joint of its name
    SourceJointKind kind = SourceJointKind::Hinge;
};

// A rotational_spring_damper on a hinge (MJCF stiffness / damping, URDF <dynamics damping>).
struct SceneForce {
    std::string name;
    std::string where;
    int parent = -1, child = -1;
    Vec3 point = Vec3::Zero(), axis = Vec3::UnitZ();
    double stiffness = 0.0, damping = 0.0, rest_angle = 0.0;
};

// A joint_stop on a hinge (coordinate angle) or slide (travel) with joint limits: a plastic
// impact at the limit (restitution 0) and a linear compliant law (hunt_crossley, exponent 1,
// no damping) that holds the joint there (docs/import.md, "Joint limits").
struct SceneStop {
    std::string name;
    std::string where;
    int parent = -1, child = -1;
    Vec3 point = Vec3::Zero(), axis = Vec3::UnitZ();
    bool travel = false;  // prismatic: the stop's coordinate is a travel
    double lower = 0.0, upper = 0.0, stiffness = 1e8;
    bool has_lower = true, has_upper = true;  // an angle limit at or beyond +-pi is left out
};

// A coordinate_coupling joint (docs/scene-format.md) between two scene joints, indices in
// ImportedScene::joints, with their positions at the start (the source's coordinates there).
struct SceneCoupling {
    std::string name;
    std::string where;
    std::string comment;
    int follower = -1, leader = -1;
    double multiplier = 1.0, offset = 0.0;
    double follower_start = 0.0, leader_start = 0.0;
};

struct ImportedScene {
    std::string name;
    std::string file;
    std::string format;
    Vec3 gravity = Vec3::Zero();
    std::vector<SceneBody> bodies;
    std::vector<SceneJoint> joints;
    std::vector<SceneForce> forces;
    std::vector<SceneStop> stops;
    std::vector<SceneCoupling> couplings;
    std::vector<Unmapped> unmapped;
    std::vector<std::string> notes;  // mapping decisions the scene's header comment states
    // index of the scene body each source body became (-1: the ground), by source index
    std::vector<int> body_of_source;
};

// The scene of a source tree: bodies welded to their parent (no joint) merged into it (to the
// ground when the parent is the world), a body with n > 1 joints given n - 1 frame bodies, a
// free joint left as a body without joint; velocities from the joints' rates. Throws
// InputError naming the element for a negative mass or an inertia that is not a rigid body's.
ImportedScene build_scene(const SourceTree& tree);

// The one-line list of what was not imported ("" when everything was).
std::string unmapped_summary(const std::vector<Unmapped>& unmapped);

}  // namespace mbd::import
