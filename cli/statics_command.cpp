// mbd statics SCENE [--json] [--output equilibrium.yaml]: static equilibrium
// (book Sec. 5.6, Eq. 6.171) with the statics plugin, its joint reactions and
// its stability. See docs/statics.md.
#include "commands.hpp"
#include "options.hpp"

#include <mbd/app/equilibrium_scene.hpp>
#include <mbd/app/json_output.hpp>
#include <mbd/app/statics_json.hpp>
#include <mbd/output_file.hpp>
#include <mbd/registry.hpp>
#include <mbd/scene.hpp>
#include <mbd/statics_analysis.hpp>
#include <mbd/viewer/animation_export.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>

namespace mbd::cli {

namespace {

struct StaticsArguments {
    std::string scene;
    bool json = false;
    std::string output;
    double time = 0.0;
    std::string objective = "auto";
    std::string hessian = "exact";
    double tolerance = 1e-10;
    int max_iterations = 500;
    bool verbose = false;
    std::string solver = "ipopt";
    std::string animation;  // --animation eq.glb | eq.html
};

bool named(const std::vector<std::string>& names, const std::string& name) {
    return std::find(names.begin(), names.end(), name) != names.end();
}

std::string quoted_list(const std::vector<std::string>& names) {
    std::string text;
    for (size_t k = 0; k < names.size(); ++k) text += (k ? ", '" : "'") + names[k] + "'";
    return text;
}

// Redundant rows: the equilibrium fixes J^T lambda, not the reactions (StaticIndeterminacy).
void print_indeterminacy(const StaticIndeterminacy& in, const std::string& stability) {
    const bool one = in.redundant_rows.size() == 1;
    std::printf("\nreactions NOT DETERMINED: %zu redundant constraint row%s (as `mbd check` names %s):\n",
                in.redundant_rows.size(), one ? "" : "s", one ? "it" : "them");
    for (const RowOwner& o : in.redundant_rows) std::printf("  %s\n", o.describe().c_str());
    std::vector<std::string> elements = in.undetermined_joints;
    for (const std::string& d : in.undetermined_drivers) elements.push_back("driver " + d);
    std::printf("so the reactions of %s hold any self-stress on top of the values below, which are the\n"
                "minimum-norm ones (no self-stress: one choice among many, not a measured load); a model\n"
                "without the redundant rows, or with compliant joints, determines them.\n",
                quoted_list(elements).c_str());
    if (stability != "not assessed")
        std::printf("the stability verdict (%s) takes the solver's own multipliers into the constraints' stiffness;\n"
                    "with a self-stress left undetermined it holds for that one only.\n",
                    stability.c_str());
}

// Each flexible body's nodes at the equilibrium (its points at the nodes' material parameters).
void print_flexible_nodes(const Model& model, const State& state) {
    for (const FlexibleBodyInstance& f : model.flexible_bodies) {
        std::printf("  %-16s (%s) nodes:\n", f.name.c_str(), f.type.c_str());
        const Eigen::VectorXd q = state.q.segment(f.offset, f.size), v = Eigen::VectorXd::Zero(f.size);
        for (int k = 0; k < f.body->node_count(); ++k) {
            const std::vector<double> xi = f.body->node_parameters(k);
            MaterialPoint p;
            f.body->point(q, v, xi.data(), p);
            if (model.dimension == Dimension::Planar)
                std::printf("    node %-9d x = %14.8g  y = %14.8g\n", k, p.r.x(), p.r.y());
            else
                std::printf("    node %-9d R = [%.8g, %.8g, %.8g]\n", k, p.r.x(), p.r.y(), p.r.z());
        }
    }
}

void print_report(const std::string& scene, const Model& model, const StaticsReport& rep,
                  const std::vector<JointLimit>& limits) {
    const StaticsResult& r = rep.result;
    const bool planar = model.dimension == Dimension::Planar;
    std::printf("statics of %s: %s (Ipopt %s, %d iterations, objective: %s)\n", scene.c_str(),
                r.converged ? "equilibrium found" : "FAILED", r.status.c_str(), r.iterations, r.objective.c_str());
    std::printf("residual: %.3e (max |C|, |Q - J^T lambda|)\n", r.residual);
    std::printf("stability: %s", r.stability.c_str());
    if (r.tangent_eigenvalues.size())
        std::printf(" (reduced Hessian on a %d-dimensional tangent space, eigenvalues %.6g .. %.6g)",
                    r.tangent_dimension, r.tangent_eigenvalues.minCoeff(), r.tangent_eigenvalues.maxCoeff());
    std::printf("\n\nbodies:\n");
    for (int b = 0; b < model.body_count(); ++b) {
        if (planar)
            std::printf("  %-16s x = %14.8g  y = %14.8g  angle = %14.8g rad\n", model.bodies[b].name.c_str(),
                        r.state.q[3 * b], r.state.q[3 * b + 1], r.state.q[3 * b + 2]);
        else
            std::printf("  %-16s R = [%.8g, %.8g, %.8g]  p = [%.8g, %.8g, %.8g, %.8g]\n", model.bodies[b].name.c_str(),
                        r.state.q[7 * b], r.state.q[7 * b + 1], r.state.q[7 * b + 2], r.state.q[7 * b + 3],
                        r.state.q[7 * b + 4], r.state.q[7 * b + 5], r.state.q[7 * b + 6]);
    }
    print_flexible_nodes(model, r.state);
    const StaticIndeterminacy& in = rep.indeterminacy;
    if (in.any()) print_indeterminacy(in, r.stability);
    if (!rep.reactions.empty()) {
        std::printf("\njoints (coordinate; reaction on the second body at the joint point, world axes%s):\n",
                    in.any() ? "; * not determined: the minimum-norm value" : "");
        for (size_t j = 0; j < rep.reactions.size(); ++j) {
            const JointLoad& l = rep.reactions[j];
            const bool undetermined = named(in.undetermined_joints, l.name);
            std::printf("%s%-16s ", undetermined ? "* " : "  ", l.name.c_str());
            if (std::isfinite(rep.coordinates[j])) std::printf("s = %12.8g  ", rep.coordinates[j]);
            else std::printf("%16s", "");
            if (planar)
                std::printf("F = [%.8g, %.8g]  T = %.8g\n", l.force.x(), l.force.y(), l.torque.z());
            else
                std::printf("F = [%.8g, %.8g, %.8g]  T = [%.8g, %.8g, %.8g]\n", l.force.x(), l.force.y(), l.force.z(),
                            l.torque.x(), l.torque.y(), l.torque.z());
        }
    }
    if (!model.drivers.empty()) {
        std::printf("\ndrivers (effort along the joint coordinate = -lambda):\n");
        const int joint_rows = r.lambda.size() - static_cast<int>(model.drivers.size());
        for (size_t d = 0; d < model.drivers.size(); ++d)
            std::printf("%s%-16s effort = %.10g\n", named(in.undetermined_drivers, model.drivers[d].name) ? "* " : "  ",
                        model.drivers[d].name.c_str(), -r.lambda[joint_rows + d]);
    }
    if (!limits.empty()) {
        std::printf("\nlimits:\n");
        for (size_t k = 0; k < limits.size(); ++k)
            std::printf("  %-16s [%g, %g]  %s  effort = %.10g\n", model.joints[limits[k].joint].name.c_str(), limits[k].lo,
                        limits[k].hi, r.limit_active[k] ? "active" : "inactive", -r.limit_multipliers[k]);
    }
}

}  // namespace

void add_statics_command(CLI::App& app, Commands& commands) {
    const auto [args, sub] = scene_subcommand<StaticsArguments>(
        app, "statics", "Static equilibrium (virtual work / minimum potential, Ipopt): configuration, reactions, stability");
    sub->add_flag("--json", args->json, "Print one JSON object instead of the report");
    sub->add_option("-o,--output", args->output, "Write the equilibrium as a scene file (positions replaced)");
    sub->add_option("--time", args->time, "Time at which the drivers hold their joints")
        ->capture_default_str()
        ->check(finite_number());
    sub->add_option("--objective", args->objective,
                    "auto (potential when every force is conservative at rest), potential, virtual-work")
        ->capture_default_str()
        ->check(CLI::IsMember({"auto", "potential", "virtual-work"}));
    sub->add_option("--hessian", args->hessian, "exact or limited-memory (potential objective)")
        ->capture_default_str()
        ->check(CLI::IsMember({"exact", "limited-memory"}));
    sub->add_option("--tolerance", args->tolerance, "Equilibrium tolerance (Ipopt tol, constr_viol_tol, dual_inf_tol)")
        ->capture_default_str()
        ->check(number_between(kSmallestTolerance, 1.0, "below 1e-14 is beneath double-precision round-off"));
    sub->add_option("--max-iterations", args->max_iterations, "Ipopt iterations")
        ->capture_default_str()
        ->check(positive_number());
    sub->add_option("--solver", args->solver, "Statics plugin type")->capture_default_str();
    sub->add_flag("--verbose", args->verbose, "Show Ipopt's iteration log");
    sub->add_option("--animation", args->animation, "Show the equilibrium as a glTF 2.0 binary (.glb) or a browser "
                                                     "viewer (.html)");

    commands[sub] = [args = args] {
        Registry registry;
        const Scene scene = read_scene_file(args->scene, registry);
        const Model& model = scene.model;
        check_output_path(args->output, scene_files(args->scene, model), "--output");
        if (!args->output.empty() && !model.flexible_bodies.empty())
            throw InputError("--output", "flexible body '" + model.flexible_bodies.front().name +
                                             "': a scene holds a flexible body in its undeformed configuration, so "
                                             "the equilibrium cannot be written as one; the report lists its nodes");
        check_animation_output(args->animation, args->scene, model);
        StaticsOptions options;
        options.time = args->time;
        options.objective = args->objective;
        options.hessian = args->hessian;
        options.tolerance = args->tolerance;
        options.max_iterations = args->max_iterations;
        options.print_level = args->verbose ? 5 : 0;
        options.limits = scene_joint_limits(model);
        const StaticsReport rep = run_statics(model, registry, options, args->solver);
        if (args->json)
            std::cout << json_text(statics_json(model, rep, options.limits)) << std::endl;
        else
            print_report(args->scene, model, rep, options.limits);
        if (!rep.result.converged) {
            std::cerr << "mbd: error: statics of " << args->scene << " failed: " << rep.result.message << '\n';
            return 1;
        }
        if (!args->output.empty()) {
            OutputFile file(args->output);
            file.replace(equilibrium_scene(scene, rep.result.state));
            file.commit();
            if (!args->json) std::cout << "\nwrote the equilibrium scene to " << args->output << '\n';
        }
        if (!args->animation.empty()) {
            State state = rep.result.state;
            state.t = args->time;
            if (state.v.size() != model.nv()) state.v = Eigen::VectorXd::Zero(model.nv());
            viewer::export_animation(model, viewer::motion_from_state(model, state, args->scene), args->animation);
            if (!args->json) std::cout << "wrote the equilibrium view to " << args->animation << '\n';
        }
        return 0;
    };
}

}  // namespace mbd::cli
