// Forward dynamics (book Sec. 1.7 and Secs. 6.6-6.12): the driver shared by every
// formulation. It creates the formulation through the registry, binds it to a
// ModelSystem, assembles a consistent initial state, integrates the formulation's
// ODE with one of the integrators of integrator.hpp, and hands each output row (motion,
// optionally joint reactions and energy / constraint diagnostics) to the sinks it is
// given (output_sink.hpp: CSV, HDF5, the animation, memory); it knows no format. A
// conservative scene whose total energy grows far beyond the scale of its motion is
// stopped as unstable (energy_growth.hpp); a stop signal ends the run at a step boundary (interrupt.hpp).
// Force elements with events (stops) need an integrator that locates them (dopri5,
// dop853, cvode); contact_events.hpp applies their impacts.
#pragma once

#include <mbd/contact_events.hpp>
#include <mbd/integrator.hpp>
#include <mbd/model.hpp>
#include <mbd/output_sink.hpp>
#include <mbd/registry.hpp>
#include <mbd/kit/formulation.hpp>

#include <Eigen/Core>

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace mbd {

struct SimulationSettings {
    std::string formulation;          // empty: the scene's `formulation:`, else the automatic choice
    std::string integrator;           // empty: the automatic choice (method_choice.hpp: dopri5 or cvode)
    IntegratorSettings integration;   // tolerance or fixed step
    // The tolerance was not given: an adaptive integrator runs at integration.tolerance or at the
    // tighter one the scene's scales need (tolerance_choice.hpp), said in the messages. False (a
    // given tolerance): it is kept, with a warning for each scale it cannot resolve.
    bool automatic_tolerance = false;
    double t_end = 1.0;
    double output_step = 0.0;         // 0: the fixed step if one is given, else t_end / 1000
    bool reactions = false;           // add JOINT.fx JOINT.fy JOINT.tz (planar) / 6 columns (spatial)
    bool diagnostics = false;         // add energies and constraint violations
    // Overrides of the scene's formulation keys (empty: keep the scene's or the default).
    std::optional<Stabilization> stabilization;
    std::optional<LinearAlgebra> algebra;
    std::optional<int> sparse_threshold;
    // Start here instead of the scene's initial state (assembled and made consistent the same way).
    std::optional<State> initial_state;
    bool progress = true;             // a progress bar on stderr when it is a terminal and the run is long
    MessageLog messages;              // the formulation's messages (default std::clog; MessageLog::silent() for none)
};

// One output sample, as given to the sample callback.
struct SimulationSample {
    State state;
    const Eigen::VectorXd* lambda = nullptr;   // multipliers when reactions were asked for, else null
    const std::vector<double>* row = nullptr;  // the output row, in SimulationResult::columns (as the sinks get it)
};

// A contact force that passed through zero (Joint::compression_sign): where the bodies would separate.
struct LiftOffRecord {
    double time = 0.0;   // interpolated between the output samples around the sign change
    std::string joint;   // the joint's name
    std::string row;     // its row's name ("contact")
};

struct SimulationResult {
    std::string formulation;
    std::string integrator;
    double tolerance = 0.0;           // of an adaptive integrator, as run (given or automatic); 0: a fixed step
    IntegratorStats stats;
    double cpu_seconds = 0.0;
    long rows = 0;                    // output samples
    std::vector<std::string> columns; // of every output row: motion_columns (csv.hpp), then reactions, diagnostics, H
    State final_state;
    double final_position_violation = 0.0;   // max |C| at the last sample
    double final_velocity_violation = 0.0;   // max |J v + C_t| at the last sample
    std::vector<EventRecord> events;         // the located events (stops closing and opening), in time order
    std::vector<LiftOffRecord> lift_offs;    // contact forces through zero, in time order (also warned of in messages)
};

// Column names of the extra CSV columns.
std::vector<std::string> reaction_columns(const Model& model);
// With --diagnostics, a scene with friction elements (Force::is_friction) also gets this column,
// last: the energy the friction dissipated since t = 0 (friction_dissipation.hpp).
constexpr const char* kFrictionDissipatedColumn = "friction_dissipated";
std::vector<std::string> diagnostic_columns();  // kinetic_energy potential_energy constraint_position_violation constraint_velocity_violation

// The output rows of a complete run: t = 0, then every output step to t_end (the last
// interval may be shorter).
long simulation_rows(const SimulationSettings& settings);

// The checks simulate() makes before any work, alone: the formulation and the integrator (named
// or chosen automatically) made, the integration settings, and what the integrator needs of the
// formulation and the scene (index-3, velocity rows, reaction loads); InputError as simulate()
// throws it. `mbd sweep` checks a study's analysis with it once, before any case.
void check_simulation_method(const Model& model, Registry& registry, const SimulationSettings& settings);

// Returns false to stop the run early.
using SimulationCallback = std::function<bool(const SimulationSample& sample)>;

// Run forward dynamics, each output row to every sink (begin() after the run's checks, end()
// once it is complete) and then to the callback. Throws InputError (unknown formulation or
// integrator, bad formulation keys, an unusable output file), KinematicsError (the initial
// state cannot be assembled), DynamicsError (the run failed at some time) or Interrupted (a
// stop signal); after a failure or a stop no sink is ended (a file sink keeps its complete
// rows in OUTPUT.partial, output_file.hpp, and the final name is not written).
SimulationResult simulate(const Model& model, Registry& registry, const SimulationSettings& settings,
                          const SimulationCallback& callback = {}, const OutputSinks& sinks = {});

}  // namespace mbd
