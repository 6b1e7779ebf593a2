// mbd simulate SCENE --t-end T --output out.csv: forward dynamics (book Secs. 6.6-6.12)
// with a formulation plugin (default: the scene's, else augmented) and an integrator
// (integrator_descriptions(), mbd/integrator.hpp), written through the output sinks
// (mbd/output_sink.hpp): the --output file in the format of its extension (CSV, HDF5;
// mbd/app/output_formats.hpp), the --animation from the same rows; optionally with joint
// reactions and energy / constraint diagnostics; --contacts writes the contacts of the same rows
// (mbd/contact_output.hpp).
#include "commands.hpp"
#include "options.hpp"

#include <mbd/app/json_output.hpp>
#include <mbd/app/output_formats.hpp>
#include <mbd/contact_output.hpp>
#include <mbd/formulation_setup.hpp>
#include <mbd/integrator.hpp>
#include <mbd/linear_algebra.hpp>
#include <mbd/interrupt.hpp>
#include <mbd/output_file.hpp>
#include <mbd/output_times.hpp>
#include <mbd/registry.hpp>
#include <mbd/scene.hpp>
#include <mbd/sdk/text.hpp>
#include <mbd/simulation.hpp>
#include <mbd/viewer/animation_sink.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>

namespace mbd::cli {

namespace {

struct SimulateArguments {
    std::string scene;
    std::string formulation;
    std::string integrator;  // empty: the automatic choice
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
    bool error_estimate = false;  // --error-estimate: a second run, 10x tighter (or half the step)
    bool json = false;
    bool tolerance_given = false, step_given = false;
    std::string animation;  // --animation out.glb | out.html
    std::string contacts;   // --contacts contacts.csv | contacts.h5
};

// The options of `mbd simulate` after SCENE; returns --tol and --step (their counts tell whether they were given).
std::pair<CLI::Option*, CLI::Option*> add_simulate_options(CLI::App* sub, SimulateArguments& a) {
    sub->add_option("--t-end", a.t_end, "End time [s]")->required()->check(positive_number());
    sub->add_option("-o,--output", a.output,
                    "Result file: t, positions, velocities (+ reactions, diagnostics); its format from the "
                    "extension: .csv (text) or .h5 (HDF5; see docs/user-guide.md)")
        ->required();
    sub->add_option("--formulation", a.formulation,
                    "Formulation plugin (default: the scene's 'formulation', else the automatic choice: embedding "
                    "for a tree (drivers on its joints prescribe their motion), augmented for closed loops; see "
                    "docs/user-guide.md)");
    const auto all = [](const IntegratorDescription&) { return true; };
    const auto adaptive = [](const IntegratorDescription& d) { return d.adaptive; };
    const auto fixed_step = [](const IntegratorDescription& d) { return !d.adaptive; };
    sub->add_option("--integrator", a.integrator,
                    "Integrator: " + integrator_list(all, ", ") + " (default: the automatic choice, " +
                        automatic_integrator(false).name + ", or " + automatic_integrator(true).name +
                        " for a stiff scene; see docs/user-guide.md)");
    CLI::Option* tol =
        sub->add_option("--tol", a.tolerance, "Tolerance of an adaptive integrator, " + integrator_list(adaptive) +
                        " (default: the automatic choice, 1e-6 or what the scene's stiction velocities need; see "
                        "docs/user-guide.md)")
            ->check(number_between(kSmallestTolerance, 1.0, "below 1e-14 is beneath double-precision round-off"));
    CLI::Option* step =
        sub->add_option("--step", a.step, "Fixed step of " + integrator_list(fixed_step) + " [s]")->check(positive_number());
    tol->excludes(step);
    step->excludes(tol);
    sub->add_option("--output-step", a.output_step,
                    "Time between output rows [s] (default: the fixed step, else t_end / 1000; at most 1e7 rows)")
        ->check(positive_number());
    sub->add_flag("--reactions", a.reactions,
                  "Add the reaction on every joint's second body at the joint point, world axes: JOINT.fx JOINT.fy "
                  "JOINT.tz (planar) or JOINT.fx JOINT.fy JOINT.fz JOINT.tx JOINT.ty JOINT.tz (spatial)");
    sub->add_flag("--diagnostics", a.diagnostics,
                  "Add kinetic_energy potential_energy constraint_position_violation constraint_velocity_violation");
    sub->add_option("--stabilization", a.stabilization, "Constraint drift control (default: projection)")
        ->check(CLI::IsMember(stabilization_names()));
    sub->add_option("--linear-algebra", a.algebra, "Linear algebra of the formulation: auto, dense or sparse")
        ->check(CLI::IsMember({"auto", "dense", "sparse"}));
    sub->add_flag("-q,--quiet", a.quiet,
                  "Quiet: no summary, no progress bar and no messages of the formulation (errors are still printed)");
    sub->add_flag("--error-estimate", a.error_estimate,
                  "Also run at a ten times tighter tolerance (fixed step: half the step) and end with the CPU time "
                  "and the estimated global error of the positions at the output times");
    sub->add_flag("--json", a.json, "Print the summary as one JSON object on stdout");
    sub->add_option("--animation", a.animation,
                    "Also write the motion as a glTF 2.0 binary (.glb) or a browser viewer (.html); see mbd animate");
    sub->add_option("--contacts", a.contacts,
                    "Also write every active contact of the bodies' collision shapes, one row per contact and output "
                    "time (bodies, point, normal, depth, normal and friction force): .csv or .h5, see docs/user-guide.md");
    return {tol, step};
}

SimulationSettings simulation_settings(const SimulateArguments& a) {
    SimulationSettings settings;
    settings.formulation = a.formulation;
    settings.integrator = a.integrator;
    if (a.tolerance > 0.0) settings.integration.tolerance = a.tolerance;
    settings.automatic_tolerance = !a.tolerance_given && !a.step_given;
    settings.integration.step = a.step;
    settings.t_end = a.t_end;
    settings.output_step = a.output_step;
    settings.reactions = a.reactions;
    settings.diagnostics = a.diagnostics;
    if (!a.stabilization.empty()) settings.stabilization = parse_stabilization(a.stabilization);
    if (!a.algebra.empty()) settings.algebra = parse_linear_algebra(a.algebra);
    settings.progress = !a.quiet;
    if (a.quiet) settings.messages = MessageLog::silent();
    return settings;
}

// --error-estimate: the mass-centre positions at the output times of this run and of
// a tighter one; their largest distance, times the Richardson factor 2^p / (2^p - 1)
// for a fixed-step integrator of order p (adaptive: the difference itself).
struct ErrorEstimate {
    double position_error = NAN;
    std::string against;  // the tighter run: "step ..." or "tol ..."
};

// A callback that keeps the mass-centre positions of every sample.
SimulationCallback collect_positions(const Model& model, std::vector<Eigen::VectorXd>& into) {
    return [&model, &into](const SimulationSample& s) {
        const int per = coordinates_per_body(model.dimension), n = model.dimension == Dimension::Planar ? 2 : 3;
        Eigen::VectorXd p(n * model.body_count());
        for (int b = 0; b < model.body_count(); ++b) p.segment(n * b, n) = s.state.q.segment(per * b, n);
        into.push_back(p);
        return true;
    };
}

ErrorEstimate estimate_error(const Model& model, Registry& registry, const SimulationSettings& settings,
                             const SimulationResult& r, const std::vector<Eigen::VectorXd>& positions) {
    ErrorEstimate out;
    SimulationSettings tight = settings;  // no sink: only the positions are kept
    tight.progress = false;
    tight.messages = MessageLog::silent();
    tight.reactions = tight.diagnostics = false;
    if (!(tight.output_step > 0.0))
        tight.output_step = settings.integration.step > 0.0 ? settings.integration.step : settings.t_end / 1000.0;
    double factor = 1.0;
    const IntegratorDescription& method = describe_integrator(r.integrator);
    if (settings.integration.step > 0.0 && !method.adaptive) {
        tight.integration.step = 0.5 * settings.integration.step;
        const double order = method.order;  // Richardson: the error falls by 2^order with half the step
        factor = std::pow(2.0, order) / (std::pow(2.0, order) - 1.0);
        out.against = "step " + format_number(tight.integration.step);
    } else {
        tight.integration.tolerance = 0.1 * r.tolerance;  // the run's own, given or automatic
        tight.automatic_tolerance = false;
        out.against = "tol " + format_number(tight.integration.tolerance);
    }
    std::vector<Eigen::VectorXd> tight_positions;
    simulate(model, registry, tight, collect_positions(model, tight_positions));
    double worst = 0.0;
    const size_t n = std::min(positions.size(), tight_positions.size());
    for (size_t k = 0; k < n; ++k) {
        const Eigen::VectorXd d = positions[k] - tight_positions[k];
        const int dim = model.dimension == Dimension::Planar ? 2 : 3;
        for (int b = 0; b < model.body_count(); ++b) worst = std::max(worst, d.segment(dim * b, dim).norm());
    }
    out.position_error = factor * worst;
    return out;
}

// The summary: one JSON object (keys in docs/user-guide.md; a non-finite value is
// null, json_output.hpp) or lines of text.
void print_simulate_summary(const SimulateArguments& a, const SimulationResult& r, const ErrorEstimate* estimate,
                            size_t estimate_outputs) {
    if (a.json) {
        Json summary = {{"scene", a.scene},
                        {"formulation", r.formulation},
                        {"integrator", r.integrator},
                        {"tolerance", r.tolerance},
                        {"t_end", a.t_end},
                        {"rows", r.rows},
                        {"steps", r.stats.steps},
                        {"rejected_steps", r.stats.rejected_steps},
                        {"rhs_evaluations", r.stats.rhs_evaluations},
                        {"cpu_s", r.cpu_seconds},
                        {"position_violation", r.final_position_violation},
                        {"velocity_violation", r.final_velocity_violation}};
        if (estimate)
            summary["error_estimate"] = {
                {"position_error", estimate->position_error}, {"cpu_s", r.cpu_seconds}, {"against", estimate->against}};
        std::cout << json_text(summary) << std::endl;
        return;
    }
    if (!a.quiet) {
        std::printf("simulated %s: t = 0 to %g s, %ld rows written to %s\n", a.scene.c_str(), a.t_end, r.rows,
                    a.output.c_str());
        std::printf("  formulation %s, integrator %s", r.formulation.c_str(), r.integrator.c_str());
        if (r.tolerance > 0.0) std::printf(", tolerance %.3g", r.tolerance);
        std::printf("\n");
        std::printf("  steps %ld, rejected %ld, rhs evaluations %ld, Jacobian evaluations %ld\n", r.stats.steps,
                    r.stats.rejected_steps, r.stats.rhs_evaluations, r.stats.jacobian_evaluations);
        if (!r.events.empty()) {
            // the located events, first and last (a resting contact may come after many rebounds)
            std::printf("  events %zu:", r.events.size());
            for (size_t k = 0; k < r.events.size(); ++k) {
                if (k == 3 && r.events.size() > 6) {
                    std::printf(" ...");
                    k = r.events.size() - 3;
                }
                const EventRecord& e = r.events[k];
                std::printf("%s %s '%s' (%s) at t = %.9g", k ? "," : "", e.kind.c_str(), e.force.c_str(),
                            e.event.c_str(), e.time);
            }
            std::printf("\n");
        }
        std::printf("  CPU time %.3f s\n", r.cpu_seconds);
        std::printf("  final constraint violation: position %.3g, velocity %.3g\n", r.final_position_violation,
                    r.final_velocity_violation);
    }
    if (estimate)
        std::printf("error estimate: CPU time %.6g s, estimated global position error %.3g m (max over %zu output "
                    "times; against a run at %s)\n",
                    r.cpu_seconds, estimate->position_error, estimate_outputs, estimate->against.c_str());
}

}  // namespace

void add_simulate_command(CLI::App& app, Commands& commands) {
    const auto [args, sub] = scene_subcommand<SimulateArguments>(
        app, "simulate", "Forward dynamics: integrate the equations of motion from the scene's initial state to t_end");
    const auto [tol, step] = add_simulate_options(sub, *args);

    commands[sub] = [args = args, tol = tol, step = step] {
        args->tolerance_given = tol->count() > 0;
        args->step_given = step->count() > 0;
        check_integrator_options(args->integrator, args->tolerance_given, args->tolerance, args->step_given, args->step,
                                 args->t_end, command_line_spelling);
        if (args->output_step > 0.0) output_intervals(args->t_end, args->output_step, "--output-step", "--t-end");
        Registry registry;
        const Model model = load_scene_file(args->scene, registry);
        check_output_path(args->output, scene_files(args->scene, model), "--output");
        const std::unique_ptr<OutputSink> output = make_output_sink(args->output, "--output");
        InterruptScope stop_on_signal;  // SIGINT/SIGTERM/SIGHUP end the run at a step boundary
        check_animation_output(args->animation, args->scene, model);
        OutputSinks sinks{output.get()};
        std::unique_ptr<OutputSink> animation;  // from the rows of this run: the viewer shows exactly the result
        if (!args->animation.empty()) sinks.push_back((animation = viewer::make_animation_sink(model, args->animation)).get());
        std::unique_ptr<OutputSink> contacts;  // the contacts at the same rows, in a table of their own
        if (!args->contacts.empty()) {
            check_output_path(args->contacts, scene_files(args->scene, model), "--contacts");
            if (args->contacts == args->output || args->contacts == args->animation)
                throw InputError("--contacts", "'" + args->contacts + "' is also the file of --output or --animation: "
                                               "give the contacts a file of their own");
            contacts = make_contact_sink(model, make_output_sink(args->contacts, "--contacts"), "--contacts");
            sinks.push_back(contacts.get());
        }

        const SimulationSettings settings = simulation_settings(*args);
        std::vector<Eigen::VectorXd> positions;
        SimulationCallback callback;
        if (args->error_estimate) callback = collect_positions(model, positions);
        const SimulationResult r = simulate(model, registry, settings, callback, sinks);
        ErrorEstimate estimate;
        if (args->error_estimate) estimate = estimate_error(model, registry, settings, r, positions);
        print_simulate_summary(*args, r, args->error_estimate ? &estimate : nullptr, positions.size());
        return 0;
    };
}

}  // namespace mbd::cli
