// Scalar scene keys addressed by a path, for studies (`mbd sweep`, Python's
// Model.with_params): read one, set one, and build a new Model from the changed scene
// without reading any file again (the Model keeps its scene document, Model::document).
//
// A path is dot-separated segments, each a key with optional [index] suffixes:
//   bodies.crank.mass            the element named `crank` of the list `bodies`
//   forces.spring.stiffness
//   joints.O.point[0]            item 0 of the list under `point`
//   bodies.rod.inertia[2][2]
//   bodies.1.mass, bodies[1].mass   the second body, by position
//   gravity[1]
// After a list key (bodies, joints, forces, drivers, actuators, or any list of named maps)
// the next segment names an element. A key the scene leaves out may be set when the map that
// would hold it exists; an absent vector key set by index (bodies.b.velocity[1]) starts as
// zeros, with 2 entries in a planar scene and 3 in a spatial one. Whether the key means
// anything is decided by the scene loader when the Model is built, as for a file.
#pragma once

#include <mbd/model.hpp>
#include <mbd/registry.hpp>
#include <mbd/sdk/params.hpp>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace mbd {

using SceneParameterValues = std::vector<std::pair<std::string, double>>;

// A path that does not resolve, or a value that cannot be set there: bad input naming the path.
class ParameterError : public InputError {
public:
    ParameterError(std::string where, const std::string& message, std::string path)
        : InputError(std::move(where), message), path_(std::move(path)) {}
    const std::string& path() const { return path_; }

private:
    std::string path_;
};

// The number at `path`; ParameterError naming the path, the segment that does not resolve and
// the nearest names there.
double scene_parameter(const Param& document, const std::string& path);

// Set the number at `path` (written with 17 significant digits, so it reads back exactly).
// ParameterError as scene_parameter; a non-finite value is refused naming the path.
void set_scene_parameter(Param& document, const std::string& path, double value);

// A Model from a scene document (the Param tree of a scene, `base:` already merged), checked
// as a scene file is; `label` stands for the file in messages.
Model load_scene_document(const Param& document, const std::string& label, Registry& registry);

// The document of a scene file as load_scene reads it (`base:` merged, every node with its
// file:line), without building a Model. Throws InputError as load_scene does for the file.
Param read_scene_document(const std::filesystem::path& file);

// The path (in the syntax above, elements by name where they have one) of the outermost node
// that starts at file:line, a list of elements giving way to its first element: the key a
// message at that location is about (a key's value, or the element that starts there).
// Empty when no node starts there.
std::string scene_key_at(const Param& document, const std::string& file, int line);

// `model` with the given keys changed: its document with each value set, built again.
// Messages name `model.source`.
Model with_scene_parameters(const Model& model, const SceneParameterValues& values, Registry& registry);

}  // namespace mbd
