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

#include <string>
#include <utility>
#include <vector>

namespace mbd {

using SceneParameterValues = std::vector<std::pair<std::string, double>>;

// The number at `path`; InputError naming the path, the segment that does not resolve and
// the nearest names there.
double scene_parameter(const Param& document, const std::string& path);

// Set the number at `path` (written with 17 significant digits, so it reads back exactly).
// InputError as scene_parameter; a non-finite value is refused naming the path.
void set_scene_parameter(Param& document, const std::string& path, double value);

// A Model from a scene document (the Param tree of a scene, `base:` already merged), checked
// as a scene file is; `label` stands for the file in messages.
Model load_scene_document(const Param& document, const std::string& label, Registry& registry);

// `model` with the given keys changed: its document with each value set, built again.
// Messages name `model.source`.
Model with_scene_parameters(const Model& model, const SceneParameterValues& values, Registry& registry);

}  // namespace mbd
