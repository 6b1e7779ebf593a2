// What a model reader hands over: the source file's bodies (MJCF bodies, URDF links) in its
// own tree, each with its pose at the model's reference configuration, its mass properties
// and the joints that connect it to its parent, all in world axes at t = 0. The readers
// (mjcf_reader.hpp, urdf_reader.hpp) fill it from their parsers; scene_builder.hpp turns it
// into mbd's bodies and joints. Nothing in it is specific to one format.
#pragma once

#include <mbd/sdk/rotation.hpp>
#include <mbd/visual.hpp>

#include <map>
#include <string>
#include <utility>
#include <vector>

namespace mbd::import {

enum class SourceJointKind { Hinge, Slide, Ball, Free, Planar, Universal, Screw };

// A joint limit at or beyond this is no limit (SDF's convention, +-1e16; mbd export writes
// kUnreachedLimit for a side without a stop, model_writers.hpp).
constexpr double kNoLimitBeyond = 1e15;

struct SourceJoint {
    std::string name;   // as in the file ("" when unnamed)
    std::string where;  // "file" or "file:line" of its definition
    SourceJointKind kind = SourceJointKind::Hinge;
    Vec3 point = Vec3::Zero();          // anchor, world, at the reference configuration
    Vec3 axis = Vec3::UnitZ();          // hinge / slide / screw axis, planar normal, world (unit)
    Vec3 axis2 = Vec3::UnitX();         // universal: the second axis (fixed in the child), world
    double pitch = 0.0;                 // screw: travel along `axis` per revolution, m (> 0 right-handed)
    // initial velocity: hinge, slide: one rate; ball: angular velocity of the child relative to
    // the parent, world (also universal); free: (velocity of the body frame's origin, angular velocity), world
    double rate = 0.0;
    Vec3 linear = Vec3::Zero(), angular = Vec3::Zero();
    // passive joint elements (hinge / slide): spring about the reference position and damping
    double stiffness = 0.0, spring_reference = 0.0, damping = 0.0;
    // hinge / slide limits, from the reference configuration (rad, m), held by a stiff stop:
    // `stop_stiffness` N m/rad or N/m (SDF <limit><stiffness>; Gazebo's 1e8 for URDF)
    bool limited = false;
    double lower = 0.0, upper = 0.0, stop_stiffness = 1e8;
    // hinge / slide / screw: the joint position at the scene's start, from the reference
    // configuration (--position; MuJoCo's qpos - qpos0, URDF / SDF joint position)
    double position = 0.0;
    // hinge / slide: MuJoCo's armature, an inertia (kg m^2, or kg) added to the joint's diagonal of
    // the joint-space mass matrix (kinetic energy 1/2 armature qdot^2)
    double armature = 0.0;
};

struct SourceBody {
    std::string name;
    std::string where;
    int parent = -1;    // index of the parent in SourceTree::bodies, -1: the world
    double mass = 0.0;
    Mat3 inertia = Mat3::Zero();        // about the mass centre, in the body frame's axes
    Vec3 origin = Vec3::Zero();         // body frame origin, world
    Mat3 rotation = Mat3::Identity();   // body frame axes -> world axes
    Vec3 com = Vec3::Zero();            // mass centre, world
    // the joints between the parent and this body, parent side first; none: welded to the parent
    std::vector<SourceJoint> joints;
    // what it looks like (URDF <visual>): shapes posed in WORLD at t = 0 (position, rotation),
    // meshes by absolute path; the scene writer poses them in the scene body's frame
    std::vector<VisualShape> visuals;
};

// A constraint that closes a loop of the tree (MJCF equality `connect` and `weld`, an SDF joint
// into a link that already has one): `joint` (or none for a weld) between two bodies of the
// tree, anchored at `joint.point`.
struct SourceLoop {
    SourceJoint joint;
    bool weld = false;  // fixes the two bodies in their relative pose at the reference configuration
    int body_a = -1, body_b = -1;  // indices in SourceTree::bodies, -1: the world
};

// A linear coupling of two one-coordinate joints (URDF <mimic>, MJCF <equality joint>):
// q_follower = multiplier * q_leader + offset, q each joint's position from the reference
// configuration (URDF: the joint position; MJCF: qpos - qpos0).
struct SourceCoupling {
    std::string name;   // the element: the mimic joint's or the equality's name
    std::string where;
    std::string what;   // "URDF mimic of joint 'j'", "MJCF equality joint 'e'"
    std::string follower, leader;  // joint names as in the file
    double multiplier = 1.0, offset = 0.0;
};

// What the file holds that the import does not map, by kind ("tendon", "sensor", ...), each
// with the element's name (and where, when the parser gives it).
struct Unmapped {
    std::string kind;
    std::vector<std::string> names;
    std::string note;  // why, or what mbd lacks
};

// A named initial state (MJCF <key>): joint positions from the reference configuration (hinge,
// slide), joint velocities in MuJoCo's qvel convention (as --velocity), and the world poses of
// free joints' bodies (frame origin, Euler parameters) that differ from qpos0.
struct SourceKeyframe {
    std::string name;
    std::map<std::string, double> positions;
    std::map<std::string, std::vector<double>> velocities;
    std::map<std::string, std::pair<Vec3, Vec4>> free_poses;
    std::vector<std::string> moved_balls;  // ball joints the keyframe turns (not supported)
};

struct SourceTree {
    std::string name;                   // the model's name
    std::string file;                   // the file it was read from
    std::string format;                 // "MJCF", "URDF" or "SDF"
    Vec3 gravity = Vec3(0, 0, -9.81);
    std::vector<SourceBody> bodies;     // parents before children
    std::vector<SourceLoop> loops;      // constraints beyond the tree
    std::vector<SourceCoupling> couplings;
    std::vector<SourceKeyframe> keyframes;
    std::vector<Unmapped> unmapped;
};

}  // namespace mbd::import
