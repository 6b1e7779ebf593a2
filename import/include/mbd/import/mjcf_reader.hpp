// MJCF through MuJoCo's own compiler (Debian libmujoco-dev): mj_loadXML compiles the file
// (defaults, classes, includes, inertiafromgeom, frames, angles in degrees are all MuJoCo's),
// and the compiled mjModel is read at its reference configuration qpos0 (mj_kinematics).
#pragma once

#include <mbd/import/source_tree.hpp>

#include <filesystem>

struct mjModel_;

namespace mbd::import {

struct MjcfCompilation;

// Throws InputError with MuJoCo's message (which has the XML line) when the file does not compile,
// or names the body whose inertia comes from a missing mesh (compile_mjcf).
SourceTree read_mjcf(const std::filesystem::path& file);

// A model compiled by the caller (a test that changes its options first); `file` labels it.
SourceTree read_mjcf_model(const mjModel_* model, const std::string& file);

// A model compiled by compile_mjcf (mjcf_compile.hpp): its placeholder geoms are not drawn and its
// missing files are listed in the tree's warning.
SourceTree read_mjcf_model(const MjcfCompilation& compiled, const std::string& file);

}  // namespace mbd::import
