// The engine's public API for programs that embed mbd (docs/embedding.md): link the CMake
// target mbd::engine of find_package(mbd) and include this header.
//
//   mbd::Registry registry;                        // plugins: the installed folder, MBD_PLUGIN_PATH
//   mbd::Model model = mbd::load_scene("pendulum.yaml", registry);
//   mbd::SimulationSettings settings;               // t_end, integrator, tolerance, ...
//   mbd::SimulationResult run = mbd::simulate(model, registry, settings, callback);
//
// The analyses: simulate (simulation.hpp), run_statics and run_inverse (statics_analysis.hpp),
// study_modes (modes_study.hpp), run_kinematics (kinematics.hpp). A Model is immutable and
// may be run by any number of threads at once; each run makes its own workspace.
#pragma once

#include <mbd/csv.hpp>               // motion_columns, motion_values: the columns of a result row
#include <mbd/kinematics.hpp>        // run_kinematics
#include <mbd/model.hpp>             // Model, State
#include <mbd/modes_study.hpp>       // study_modes
#include <mbd/registry.hpp>          // Registry: the plugin path
#include <mbd/scene.hpp>             // load_scene, load_scene_text
#include <mbd/simulation.hpp>        // simulate
#include <mbd/simulator.hpp>         // Simulator: step, advance_to, inputs, a user force
#include <mbd/statics_analysis.hpp>  // run_statics, run_inverse

namespace mbd {

// The version of the engine library loaded ("0.1.0"), as the package's mbd_VERSION.
const char* engine_version();

}  // namespace mbd
