// The import layer's entry points (docs/import.md): a model file (MJCF, URDF, SDF) read by its own
// parser into an mbd scene, and the loader that takes a scene or a model file wherever a
// command accepts a scene, knowing the format from the file's content.
#pragma once

#include <mbd/import/imported_scene.hpp>
#include <mbd/model.hpp>
#include <mbd/registry.hpp>

#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace mbd::import {

struct ImportOptions {
    // initial joint positions by joint name (hinge, slide, screw): the angle or travel from the
    // model's reference configuration (MuJoCo's qpos - qpos0, URDF / SDF joint position)
    std::map<std::string, double> joint_positions;
    // initial joint velocities by joint name, in MuJoCo's qvel convention: hinge and slide one
    // rate (screw: the turning rate); universal two, the rates about its first and second
    // axes; ball the angular velocity in the body's axes; free / floating six numbers, the
    // velocity of the body frame's origin in world axes, then the angular velocity in body axes
    std::map<std::string, std::vector<double>> joint_velocities;
    // an MJCF keyframe by name: its joint positions and velocities (and free bodies' poses) are the
    // start; joint_positions and joint_velocities given beside it take precedence
    std::string keyframe;
};

// Moves the tree to the positions of `options`: the body of each joint and all its descendants
// (and the body's later joints) turned about / moved along the joint's axis, and the joint's
// spring reference shifted by as much (mbd's coordinates are zero at the scene's start).
// InputError for an unknown joint or one that is not a hinge, slide or screw.
void apply_joint_positions(SourceTree& tree, const ImportOptions& options);

// Sets the velocities of `options` on the tree's joints; InputError for an unknown joint or a
// wrong count of numbers.
void apply_joint_velocities(SourceTree& tree, const ImportOptions& options);

// The source tree of an MJCF, URDF or SDF file (InputError for an mbd scene).
SourceTree read_model_file(const std::filesystem::path& file);

// read_model_file, the options' positions and velocities, build_scene.
ImportedScene import_model(const std::filesystem::path& file, const ImportOptions& options = {});

// A scene file (YAML) as load_scene does, or a model file imported with default options;
// `warn` receives the one-line list of what the import left out (not called when nothing was).
Model load_scene_or_model(const std::filesystem::path& file, Registry& registry,
                          const std::function<void(const std::string&)>& warn);

}  // namespace mbd::import
