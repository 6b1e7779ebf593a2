// An ExportTree (export_tree.hpp) as the text of a model file: MJCF (mjcf_writer.cpp) for
// MuJoCo and URDF (urdf_writer.cpp) for ROS tools, written through TinyXML (the XML library the
// URDF reader already uses), every number with 17 significant digits so that the model is
// reproduced exactly (docs/import.md, "Export").
#pragma once

#include <mbd/import/export_tree.hpp>

#include <string>
#include <vector>

namespace mbd::import {

// The side of a joint's limits that has no stop (URDF requires both sides of a revolute or
// prismatic joint's limits, MJCF both sides of a range): a limit no motion reaches, which the
// import reads back as no limit (at or beyond kNoLimitBeyond, source_tree.hpp; docs/import.md).
constexpr double kUnreachedLimit = 1e16;

// MJCF: nested bodies (frame at the mass centre, full inertia), hinge / slide / ball / free
// joints with the hinges' spring-dampers and limits (joint stops), gravity, and the start's velocities as the keyframe
// "start" (MuJoCo's qvel; qpos is the reference configuration).
std::string mjcf_text(const ExportTree& tree);

// URDF: links with their inertials, continuous / revolute (a hinge with a stop) / prismatic /
// fixed / floating / planar joints with their limits,
// rooted at a link "world". Appends to `left_out` what URDF cannot hold (gravity other than
// 9.81 down, spring-dampers, initial velocities); throws InputError naming the joints for a ball
// joint (URDF has none: export MJCF).
std::string urdf_text(const ExportTree& tree, std::vector<Unmapped>& left_out);

}  // namespace mbd::import

namespace mbd::import {

// The written text read back by the format's own parser before it is saved: MuJoCo's compiler
// (from memory) for MJCF, urdfdom for URDF. Throws InputError naming `output` with the parser's
// message when it refuses the text (a model MuJoCo cannot hold, e.g. a mass below its minimum).
void check_written_mjcf(const std::string& text, const std::string& output);
void check_written_urdf(const std::string& text, const std::string& output);

}  // namespace mbd::import
