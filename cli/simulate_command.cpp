// mbd simulate SCENE --t-end T --output out.csv: forward dynamics (book Secs. 6.6-6.12)
// with a formulation plugin (default: the scene's, else augmented) and an integrator
// (rk4, dopri5, generalized_alpha, cvode), written in the CSV contract of mbd/csv.hpp,
// optionally with joint reactions and energy / constraint diagnostics.
#include "commands.hpp"
#include "options.hpp"

#include <mbd/app/json_output.hpp>
#include <mbd/integrator.hpp>
#include <mbd/linear_algebra.hpp>
#include <mbd/interrupt.hpp>
#include <mbd/output_file.hpp>
#include <mbd/output_times.hpp>
#include <mbd/registry.hpp>
#include <mbd/scene.hpp>
#include <mbd/sdk/text.hpp>
#include <mbd/simulation.hpp>
#include <mbd/viewer/animation_export.hpp>

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
    bool error_estimate = false;  // --error-estimate: a second run, 10x tighter (or half the step)
    bool json = false;
    bool tolerance_given = false, step_given = false;
    std::string animation;  // --animation out.glb | out.html
};

// --tol belongs to the adaptive integrators, --step to the fixed-step ones (docs/integrators.md);
// an option that does not apply is an error rather than quietly taking another meaning.
void check_integrator_options(const SimulateArguments& a) {
    const bool adaptive = make_integrator(a.integrator, IntegratorSettings{})->adaptive();
    if (adaptive && a.step_given)
        throw InputError("--step", "applies to the fixed-step integrators (rk4, euler, generalized_alpha); " +
                                       a.integrator +
                                       " chooses its own steps: set its accuracy with --tol and the time between "
                                       "rows with --output-step");
    if (!adaptive && a.tolerance_given)
        throw InputError("--tol", "applies to the adaptive integrators (dopri5, cvode); " + a.integrator +
                                      " takes fixed steps: set them with --step");
    if (!adaptive && !a.step_given)
        throw InputError("--step", a.integrator + " takes fixed steps: give their size with --step (e.g. --step " +
                                       "1e-3), or choose an adaptive integrator (--integrator dopri5 or cvode)");
    if (a.step_given) {
        const double steps = a.t_end / a.step;
        const long limit = IntegratorSettings{}.max_steps;
        if (!(steps <= static_cast<double>(limit))) {
            char text[200];
            std::snprintf(text, sizeof text, "%g needs %.3g steps to reach --t-end %g; at most %ld are taken: use a "
                          "larger step", a.step, steps, a.t_end, limit);
            throw InputError("--step", text);
        }
    }
}

}  // namespace

void add_simulate_command(CLI::App& app, Commands& commands) {
    CLI::App* sub = app.add_subcommand("simulate", "Forward dynamics: integrate the equations of motion from the scene's "
                                                   "initial state to t_end");
    auto args = std::make_shared<SimulateArguments>();
    sub->add_option("SCENE", args->scene, "Scene file (YAML)")->required();
    sub->add_option("--t-end", args->t_end, "End time [s]")->required()->check(positive_number());
    sub->add_option("-o,--output", args->output, "CSV file: t, positions, velocities (+ reactions, diagnostics)")
        ->required();
    sub->add_option("--formulation", args->formulation,
                    "Formulation plugin (default: the scene's 'formulation', else augmented)");
    sub->add_option("--integrator", args->integrator, "Integrator: rk4, dopri5, generalized_alpha, cvode")
        ->capture_default_str();
    CLI::Option* tol =
        sub->add_option("--tol", args->tolerance, "Tolerance of an adaptive integrator, dopri5 or cvode (default 1e-6)")
            ->check(number_between(kSmallestTolerance, 1.0, "below 1e-14 is beneath double-precision round-off"));
    CLI::Option* step =
        sub->add_option("--step", args->step, "Fixed step of rk4, euler or generalized_alpha [s]")->check(positive_number());
    tol->excludes(step);
    step->excludes(tol);
    sub->add_option("--output-step", args->output_step,
                    "Time between CSV rows [s] (default: the fixed step, else t_end / 1000; at most 1e7 rows)")
        ->check(positive_number());
    sub->add_flag("--reactions", args->reactions,
                  "Add the reaction on every joint's second body at the joint point, world axes: JOINT.fx JOINT.fy "
                  "JOINT.tz (planar) or JOINT.fx JOINT.fy JOINT.fz JOINT.tx JOINT.ty JOINT.tz (spatial)");
    sub->add_flag("--diagnostics", args->diagnostics,
                  "Add kinetic_energy potential_energy constraint_position_violation constraint_velocity_violation");
    sub->add_option("--stabilization", args->stabilization, "Constraint drift control (default: projection)")
        ->check(CLI::IsMember({"projection", "baumgarte", "none"}));
    sub->add_option("--linear-algebra", args->algebra, "Linear algebra of the formulation: auto, dense or sparse")
        ->check(CLI::IsMember({"auto", "dense", "sparse"}));
    sub->add_flag("-q,--quiet", args->quiet,
                  "Quiet: no summary, no progress bar and no messages of the formulation (errors are still printed)");
    sub->add_flag("--error-estimate", args->error_estimate,
                  "Also run at a ten times tighter tolerance (fixed step: half the step) and end with the CPU time "
                  "and the estimated global error of the positions at the output times");
    sub->add_flag("--json", args->json, "Print the summary as one JSON object on stdout");
    sub->add_option("--animation", args->animation,
                    "Also write the motion as a glTF 2.0 binary (.glb) or a browser viewer (.html); see mbd animate");

    commands[sub] = [args, tol, step] {
        args->tolerance_given = tol->count() > 0;
        args->step_given = step->count() > 0;
        check_integrator_options(*args);
        if (args->output_step > 0.0) output_intervals(args->t_end, args->output_step, "--output-step", "--t-end");
        Registry registry;
        const Model model = load_scene(args->scene, registry);
        check_output_path(args->output, scene_files(args->scene, model), "--output");
        InterruptScope stop_on_signal;  // SIGINT/SIGTERM/SIGHUP end the run at a step boundary
        check_animation_output(args->animation, args->scene, model);

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
        if (!args->algebra.empty()) settings.algebra = parse_linear_algebra(args->algebra);
        settings.progress = !args->quiet;
        if (args->quiet) settings.messages = MessageLog::silent();

        // --error-estimate: the mass-centre positions at the output times of this run and of
        // a tighter one; their largest distance, times the Richardson factor 2^p / (2^p - 1)
        // for a fixed-step integrator of order p (adaptive: the difference itself).
        std::vector<Eigen::VectorXd> positions, tight_positions;
        auto collect = [&model](std::vector<Eigen::VectorXd>& into) {
            return [&model, &into](const SimulationSample& s) {
                const int per = coordinates_per_body(model.dimension), n = model.dimension == Dimension::Planar ? 2 : 3;
                Eigen::VectorXd p(n * model.body_count());
                for (int b = 0; b < model.body_count(); ++b) p.segment(n * b, n) = s.state.q.segment(per * b, n);
                into.push_back(p);
                return true;
            };
        };
        SimulationCallback callback;
        if (args->error_estimate) callback = collect(positions);
        const SimulationResult r = simulate(model, registry, settings, callback);
        double estimate = NAN;
        std::string against;
        if (args->error_estimate) {
            SimulationSettings tight = settings;
            tight.output.clear();
            tight.progress = false;
            tight.messages = MessageLog::silent();
            tight.reactions = tight.diagnostics = false;
            if (!(tight.output_step > 0.0))
                tight.output_step = settings.integration.step > 0.0 ? settings.integration.step : settings.t_end / 1000.0;
            double factor = 1.0;
            if (settings.integration.step > 0.0 && (r.integrator == "euler" || r.integrator == "rk4" ||
                                                   r.integrator == "generalized_alpha")) {
                tight.integration.step = 0.5 * settings.integration.step;
                const double order = r.integrator == "euler" ? 1.0 : r.integrator == "rk4" ? 4.0 : 2.0;
                factor = std::pow(2.0, order) / (std::pow(2.0, order) - 1.0);
                against = "step " + format_number(tight.integration.step);
            } else {
                tight.integration.tolerance = 0.1 * settings.integration.tolerance;
                against = "tol " + format_number(tight.integration.tolerance);
            }
            simulate(model, registry, tight, collect(tight_positions));
            double worst = 0.0;
            const size_t n = std::min(positions.size(), tight_positions.size());
            for (size_t k = 0; k < n; ++k) {
                const Eigen::VectorXd d = positions[k] - tight_positions[k];
                const int dim = model.dimension == Dimension::Planar ? 2 : 3;
                for (int b = 0; b < model.body_count(); ++b) worst = std::max(worst, d.segment(dim * b, dim).norm());
            }
            estimate = factor * worst;
        }
        if (!args->animation.empty())  // from the CSV just written: the viewer shows exactly the result
            viewer::export_animation(model, viewer::read_motion_csv(args->output), args->animation);
        if (args->json) {  // keys in docs/user-guide.md; a non-finite value is null (json_output.hpp)
            Json summary = {{"scene", args->scene},
                            {"formulation", r.formulation},
                            {"integrator", r.integrator},
                            {"t_end", args->t_end},
                            {"rows", r.rows},
                            {"steps", r.stats.steps},
                            {"rejected_steps", r.stats.rejected_steps},
                            {"rhs_evaluations", r.stats.rhs_evaluations},
                            {"cpu_s", r.cpu_seconds},
                            {"position_violation", r.final_position_violation},
                            {"velocity_violation", r.final_velocity_violation}};
            if (args->error_estimate)
                summary["error_estimate"] = {{"position_error", estimate}, {"cpu_s", r.cpu_seconds}, {"against", against}};
            std::cout << json_text(summary) << std::endl;
            return 0;
        }
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
        if (args->error_estimate)
            std::printf("error estimate: CPU time %.6g s, estimated global position error %.3g m (max over %zu output "
                        "times; against a run at %s)\n",
                        r.cpu_seconds, estimate, positions.size(), against.c_str());
        return 0;
    };
}

}  // namespace mbd::cli
