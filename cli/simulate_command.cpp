// mbd simulate SCENE --t-end T --output out.csv: forward dynamics (book Secs. 6.6-6.12)
// with a formulation plugin (default: the scene's, else augmented) and an integrator
// (rk4, dopri5, generalized_alpha, cvode), written in the CSV contract of mbd/csv.hpp,
// optionally with joint reactions and energy / constraint diagnostics.
#include "commands.hpp"

#include <mbd/registry.hpp>
#include <mbd/scene.hpp>
#include <mbd/simulation.hpp>

#include <cstdio>
#include <iostream>
#include <memory>

namespace mbd::cli {

namespace {

struct SimulateArguments {
    std::string scene;
    std::string formulation;
    std::string integrator = "dopri5";
    double tolerance = 0.0;
    double step = 0.0;
    double t_end = 0.0;
    std::string output;
    double output_step = 0.0;
    bool reactions = false;
    bool diagnostics = false;
    std::string stabilization;
    std::string algebra;
    bool quiet = false;
};

}  // namespace

void add_simulate_command(CLI::App& app, Commands& commands) {
    CLI::App* sub = app.add_subcommand("simulate", "Forward dynamics: integrate the equations of motion from the scene's "
                                                   "initial state to t_end");
    auto args = std::make_shared<SimulateArguments>();
    sub->add_option("SCENE", args->scene, "Scene file (YAML)")->required();
    sub->add_option("--t-end", args->t_end, "End time [s]")->required()->check(CLI::PositiveNumber);
    sub->add_option("-o,--output", args->output, "CSV file: t, positions, velocities (+ reactions, diagnostics)")
        ->required();
    sub->add_option("--formulation", args->formulation,
                    "Formulation plugin (default: the scene's 'formulation', else augmented)");
    sub->add_option("--integrator", args->integrator, "Integrator: rk4, dopri5, generalized_alpha, cvode")
        ->capture_default_str();
    CLI::Option* tol = sub->add_option("--tol", args->tolerance, "Tolerance of an adaptive integrator (default 1e-6)")
                           ->check(CLI::PositiveNumber);
    CLI::Option* step = sub->add_option("--step", args->step, "Fixed step (rk4, generalized_alpha) [s]")
                            ->check(CLI::PositiveNumber);
    tol->excludes(step);
    step->excludes(tol);
    sub->add_option("--output-step", args->output_step,
                    "Time between CSV rows [s] (default: the fixed step, else t_end / 1000)")
        ->check(CLI::PositiveNumber);
    sub->add_flag("--reactions", args->reactions,
                  "Add the reaction on every joint's second body at the joint point, world axes: JOINT.fx JOINT.fy "
                  "JOINT.tz (planar) or JOINT.fx JOINT.fy JOINT.fz JOINT.tx JOINT.ty JOINT.tz (spatial)");
    sub->add_flag("--diagnostics", args->diagnostics,
                  "Add kinetic_energy potential_energy constraint_position_violation constraint_velocity_violation");
    sub->add_option("--stabilization", args->stabilization, "Constraint drift control (default: projection)")
        ->check(CLI::IsMember({"projection", "baumgarte", "none"}));
    sub->add_option("--linear-algebra", args->algebra, "Linear algebra of the formulation: auto, dense or sparse")
        ->check(CLI::IsMember({"auto", "dense", "sparse"}));
    sub->add_flag("-q,--quiet", args->quiet, "No summary and no progress bar");

    commands[sub] = [args] {
        Registry registry;
        const Model model = load_scene(args->scene, registry);

        SimulationSettings settings;
        settings.formulation = args->formulation;
        settings.integrator = args->integrator;
        if (args->tolerance > 0.0) settings.integration.tolerance = args->tolerance;
        settings.integration.step = args->step;
        settings.t_end = args->t_end;
        settings.output_step = args->output_step;
        settings.output = args->output;
        settings.reactions = args->reactions;
        settings.diagnostics = args->diagnostics;
        if (args->stabilization == "projection") settings.stabilization = Stabilization::Projection;
        if (args->stabilization == "baumgarte") settings.stabilization = Stabilization::Baumgarte;
        if (args->stabilization == "none") settings.stabilization = Stabilization::None;
        settings.algebra = args->algebra;
        settings.progress = !args->quiet;

        const SimulationResult r = simulate(model, registry, settings);
        if (!args->quiet) {
            std::printf("simulated %s: t = 0 to %g s, %ld rows written to %s\n", args->scene.c_str(), args->t_end,
                        r.rows, args->output.c_str());
            std::printf("  formulation %s, integrator %s\n", r.formulation.c_str(), r.integrator.c_str());
            std::printf("  steps %ld, rejected %ld, rhs evaluations %ld, Jacobian evaluations %ld\n", r.stats.steps,
                        r.stats.rejected_steps, r.stats.rhs_evaluations, r.stats.jacobian_evaluations);
            std::printf("  CPU time %.3f s\n", r.cpu_seconds);
            std::printf("  final constraint violation: position %.3g, velocity %.3g\n", r.final_position_violation,
                        r.final_velocity_violation);
        }
        return 0;
    };
}

}  // namespace mbd::cli
