// The set-up shared by a whole run (simulate, simulation.cpp) and a stepped one (Simulator,
// simulator.cpp): the formulation and integrator made and checked against each other and the
// scene, and the consistent start the formulation integrates from.
#pragma once

#include <mbd/contact_events.hpp>
#include <mbd/integrator.hpp>
#include <mbd/model_system.hpp>
#include <mbd/simulation.hpp>

#include <memory>
#include <string>
#include <vector>

namespace mbd {

// The formulation and integrator of a run, made and checked against each other and the scene
// before any work (the checks of check_simulation_method).
struct PreparedRun {
    std::string formulation_name;
    FormulationOptions options;
    std::shared_ptr<Formulation> formulation;
    std::unique_ptr<Integrator> integrator;
    IntegratorSettings integration;  // the tolerance chosen or given (run_integration)
};
PreparedRun prepare_run(const Model& model, Registry& registry, const SimulationSettings& settings);

// Forward dynamics solves M vdot = ...: a zero mass or principal moment is refused by name.
void require_positive_masses(const Model& model);

// Assembles `state` at time t onto the constraints in place (positions, then velocities;
// drivers included) and returns it as the formulation's y, projected. Throws KinematicsError / DynamicsError.
Eigen::VectorXd consistent_start(ModelSystem& system, Formulation& formulation, State& state, double t);

// A scene with events (a stop's closing and opening) needs an integrator that locates them;
// the start's sides of every event function are checked against the elements' states.
void start_events(ContactEvents& events, const Integrator& integrator, const State& state);

// The scene's time functions {type: input, name: NAME}, in the order of the document (a
// name may repeat: one input read by several elements).
struct SceneInput {
    std::string name;
    std::string where;  // file:line
};
std::vector<SceneInput> scene_inputs(const Model& model);
// The breakpoints of the scene's piecewise-constant time functions ({type: steps, table:
// [[t0, f0], ...]}: every t_k after the first), increasing, each once: the run's steps end on
// them (step_toward, integrator.hpp). A table time the document does not hold as a number
// (none today: tables are numbers) gives none.
std::vector<double> scene_breakpoints(const Model& model);
// A whole run (simulate) has no inputs: InputError at the first input of the scene.
void refuse_scene_inputs(const Model& model);

}  // namespace mbd
