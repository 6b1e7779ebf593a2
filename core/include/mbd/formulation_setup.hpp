// A run's formulation from the scene's `formulation:` node: the shared keys read once
// into the typed FormulationOptions (kit formulation_options.hpp), the plugin created
// through the registry, and every key checked: a shared key must belong to a group the
// formulation honours (Formulation::options_used()), any other key must be one the
// plugin read itself.
#pragma once

#include <mbd/model.hpp>
#include <mbd/registry.hpp>
#include <mbd/kit/formulation.hpp>

#include <memory>
#include <string>
#include <vector>

namespace mbd {

// The constraint stabilizations by name, in the order they are listed to the user:
// "projection", "baumgarte", "none". parse_stabilization throws InputError (no key: the
// caller names its option) for another name, listing them.
std::vector<std::string> stabilization_names();
Stabilization parse_stabilization(const std::string& name);

// The shared keys of a `formulation:` node (a name, or a map with `type`), each checked at
// its file:line; absent keys keep their defaults. Throws InputError.
FormulationOptions read_formulation_options(const Param& node);

// Create the formulation NAME. `node` is the scene's `formulation:` node (null: none);
// `where` names the place for an unknown-type error. Throws InputError on an unknown
// type or key.
std::shared_ptr<Formulation> create_formulation(Registry& registry, const std::string& name, const Param* node,
                                                const std::string& where);

// A model with velocity-level (nonholonomic) joint rows needs a formulation that obeys them
// (Formulation::supports_velocity_constraints) and, when the integrator solves the index-3
// DAE on the holonomic rows (needs_index3, named `integrator`), refuses that too. Throws
// InputError naming the first such joint, the formulation and what to use instead.
void require_velocity_rows_handled(const Model& model, const Formulation& formulation, const std::string& name,
                                   bool needs_index3, const std::string& integrator);

// A model with force elements loaded by a joint's reaction (Force::load_joint) needs a
// formulation that solves those loads with its multipliers (supports_reaction_loads) and an
// integrator that works through the formulation (not needs_index3). Throws InputError naming
// the first such element.
void require_reaction_loads_handled(const Model& model, const Formulation& formulation, const std::string& name,
                                    bool needs_index3, const std::string& integrator);
// A scene with flexible bodies (Model::flexible_bodies) needs a formulation that takes them
// (Formulation::supports_flexible_bodies) and an integrator that does not solve the index-3
// equations on the system: throws InputError at the first flexible body, naming it and what to use.
void require_flexible_bodies_handled(const Model& model, const Formulation& formulation, const std::string& name,
                                     bool needs_index3, const std::string& integrator);

}  // namespace mbd
