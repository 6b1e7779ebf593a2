// An mbd model as the tree that MJCF and URDF describe (docs/import.md, "Export"): every body with
// its world pose at the scene's assembled start, its mass properties and the joints that move it
// relative to its parent (none: welded to the parent). Built from a loaded Model by
// build_export_tree; written by mjcf_writer.hpp and urdf_writer.hpp. What the tree cannot hold
// (drivers, loop-closing or unsupported joints, force elements other than gravity, a
// rotational spring-damper on a hinge and a joint_stop on a hinge or slide) is listed by name in `left_out`, never dropped silently.
#pragma once

#include <mbd/import/source_tree.hpp>  // Unmapped
#include <mbd/model.hpp>

#include <string>
#include <vector>

namespace mbd::import {

enum class ExportJointKind { Hinge, Slide, Ball, Free };

struct ExportJoint {
    std::string name;
    ExportJointKind kind = ExportJointKind::Hinge;
    Vec3 point = Vec3::Zero();  // anchor, world, at the start
    Vec3 axis = Vec3::UnitZ();  // hinge / slide axis, world (unit)
    // initial velocity in MuJoCo's qvel convention: hinge, slide one rate; ball the angular
    // velocity relative to the parent in the body's axes; free the velocity of the body's origin
    // (world) then its angular velocity (body axes)
    std::vector<double> velocity;
    // a hinge's spring-damper (MJCF stiffness, springref from the start, damping)
    double stiffness = 0.0, damping = 0.0, spring_reference = 0.0;
    std::string spring_name;  // the rotational_spring_damper it carries ("" none)
    // MJCF armature: the axial moment times multiplier^2 of a rotor pinned to the ground and
    // coupled to this joint's coordinate (the form the MJCF import gives armature; docs/import.md)
    double armature = 0.0;
    std::string rotor;  // that rotor body ("" none)
    // a joint_stop on a hinge or slide as the joint's limits (MJCF range, URDF <limit>), in the
    // joint's coordinate (zero at the start); a side without a limit is not set
    bool has_lower = false, has_upper = false;
    double lower = 0.0, upper = 0.0;
    std::string stop_name;  // the joint_stop it carries ("" none)
};

struct ExportBody {
    std::string name;
    int parent = -1;       // index in ExportTree::bodies (parents first), -1: the world
    std::string welded_by;  // the fixed joint that welds it to its parent ("" when it has joints)
    double mass = 0.0;
    Mat3 inertia = Mat3::Zero();       // about the mass centre, body axes
    Vec3 position = Vec3::Zero();      // mass centre = the body frame's origin, world
    Mat3 rotation = Mat3::Identity();  // body axes -> world
    std::vector<ExportJoint> joints;   // in MuJoCo's order (a planar free body: slide x, slide y, hinge z)
};

struct ExportTree {
    std::string name;
    std::string source;
    bool planar = false;  // a planar scene, exported as spatial (docs/import.md)
    Vec3 gravity = Vec3::Zero();
    std::vector<ExportBody> bodies;
    std::vector<Unmapped> left_out;
};

// Throws KinematicsError when the scene cannot be assembled at t = 0.
ExportTree build_export_tree(const Model& model);

}  // namespace mbd::import
