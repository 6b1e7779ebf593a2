// `mbd plugin check LIB.so`: load a joint or force plugin library and validate
// every type it provides: its ABI, its Jacobians and gamma (and a joint's
// driver coordinate) against finite differences on random states, force
// Jacobians and Q = -dV/dq, and finite output on degenerate input. The joint
// geometry is random too (seeded by --seed): a random joint point, so the marker
// offsets from the mass centres are non-zero, random axes, and random `points`
// (one per body) when the joint accepts that key. Each
// failure is printed with the state that shows it; the exit status says pass
// (0) or fail (1).
#include "commands.hpp"

#include <mbd/body_poses.hpp>
#include <mbd/derivative_check.hpp>
#include <mbd/registry.hpp>
#include <mbd/scene.hpp>
#include <mbd/sdk/domain_error.hpp>

#include <cstdio>
#include <iostream>
#include <memory>
#include <random>
#include <sstream>

namespace mbd::cli {
namespace {

struct CheckOptions {
    std::string library;
    std::vector<std::string> params;  // extra YAML keys for the element, e.g. "ratio: 2", one per entry
    double tolerance = 1e-6;
    unsigned seed = 20261121;
};

// The element's own keys, indented under its list item.
std::string extra_keys(const std::vector<std::string>& params) {
    std::ostringstream out;
    for (const std::string& line : params)
        if (!line.empty()) out << "    " << line << "\n";
    return out.str();
}

// Two-body test scenes in which the element connects ground-body and body-body; with_points:
// a `points` key (one point per body, body axes) for joints that take their points so. The
// geometry written here is a placeholder: with_random_joint_geometry draws it.
std::string joint_scene(Dimension d, const std::string& type, const std::vector<std::string>& params, bool with_points) {
    std::ostringstream s;
    const std::string points = !with_points ? ""
                               : d == Dimension::Planar ? "    points: [[0.1, 0.2], [0.3, -0.1]]\n"
                                                        : "    points: [[0.1, 0.2, 0.3], [0.3, -0.1, 0.2]]\n";
    if (d == Dimension::Planar) {
        s << "dimension: planar\nbodies:\n"
          << "  - {name: a, mass: 1.3, inertia: 0.2, position: [0.3, 0.1], angle: 0.2}\n"
          << "  - {name: b, mass: 0.7, inertia: 0.1, position: [0.8, -0.2], angle: -0.4}\n"
          << "joints:\n"
          << "  - name: to_ground\n    type: " << type << "\n    bodies: [ground, a]\n    point: [0.1, 0.05]\n"
          << "    axis: [0.6, 0.8]\n" << points << extra_keys(params)
          << "  - name: between\n    type: " << type << "\n    bodies: [a, b]\n    point: [0.5, 0.0]\n"
          << "    axis: [0.6, 0.8]\n" << points << extra_keys(params);
    } else {
        s << "dimension: spatial\nbodies:\n"
          << "  - {name: a, mass: 1.3, inertia: [0.2, 0.3, 0.4], position: [0.3, 0.1, 0.2], "
             "orientation: {axis: [1, 2, 3], angle: 0.5}}\n"
          << "  - {name: b, mass: 0.7, inertia: [0.1, 0.2, 0.25], position: [0.8, -0.2, 0.1], "
             "orientation: {axis: [-1, 0.5, 2], angle: 1.1}}\n"
          << "joints:\n";
        for (const char* name : {"to_ground", "between"}) {
            s << "  - name: " << name << "\n    type: " << type << "\n    bodies: "
              << (std::string(name) == "to_ground" ? "[ground, a]" : "[a, b]")
              << "\n    point: [0.5, 0.1, 0.2]\n    axes: [[0.3, 0.4, 0.866], [0.8, -0.6, 0.0]]\n"
              << points << extra_keys(params);
        }
    }
    return s.str();
}

// A random point in body axes, written for a scene (non-zero offsets from the mass centre).
std::string random_point(Dimension d, std::mt19937& rng) {
    std::uniform_real_distribution<double> u(-0.5, 0.5);
    std::ostringstream s;
    s.precision(17);
    s << "[" << u(rng) << ", " << u(rng);
    if (d == Dimension::Spatial) s << ", " << u(rng);
    s << "]";
    return s.str();
}

std::string force_scene(Dimension d, const std::string& type, const std::vector<std::string>& params, bool two_bodies,
                        std::mt19937& rng) {
    std::ostringstream s;
    const bool planar = d == Dimension::Planar;
    s << "dimension: " << (planar ? "planar" : "spatial") << "\n";
    if (type == "gravity") s << "gravity: " << (planar ? "[0.3, -9.81]" : "[0.3, -9.81, 0.2]") << "\n";
    s << "bodies:\n";
    if (planar)
        s << "  - {name: a, mass: 1.3, inertia: 0.2, position: [0.3, 0.1], angle: 0.2}\n"
          << "  - {name: b, mass: 0.7, inertia: 0.1, position: [0.8, -0.2], angle: -0.4}\n";
    else
        s << "  - {name: a, mass: 1.3, inertia: [0.2, 0.3, 0.4], position: [0.3, 0.1, 0.2], "
             "orientation: {axis: [1, 2, 3], angle: 0.5}}\n"
          << "  - {name: b, mass: 0.7, inertia: [0.1, 0.2, 0.25], position: [0.8, -0.2, 0.1], "
             "orientation: {axis: [-1, 0.5, 2], angle: 1.1}}\n";
    if (type == "gravity") return s.str();
    s << "forces:\n  - name: element\n    type: " << type << "\n";
    if (two_bodies)
        s << "    bodies: [a, b]\n    points: [" << random_point(d, rng) << ", " << random_point(d, rng) << "]\n";
    else
        s << "    body: a\n    point: " << random_point(d, rng) << "\n";
    s << extra_keys(params);
    return s.str();
}

// Evaluate every element at a degenerate state (all bodies at the origin, at
// rest, then moving fast): the outputs must stay finite.
bool finite_on_degenerate_input(const Model& model) {
    for (double speed : {0.0, 1e3}) {
        State s = model.initial_state();
        for (int b = 0; b < model.body_count(); ++b) {
            s.q.segment(model.q_offset(b), 3).setZero();
            if (model.dimension == Dimension::Spatial) s.q.segment<4>(model.q_offset(b) + 3) << 1, 0, 0, 0;
        }
        s.v.setConstant(speed);
        BodyPoses poses(model);
        poses.update(s);
        const int nvb = velocities_per_body(model.dimension);
        for (const JointInstance& j : model.joints) {
            ConstraintEval e;
            e.resize(j.joint->rows(), nvb * static_cast<int>(j.bodies.size()));
            try {
                j.joint->evaluate(poses.view(j.bodies, s.t), e);
            } catch (const DomainError&) {
                continue;  // a state outside the joint's geometry, refused by name: not a NaN
            }
            if (!(e.C.allFinite() && e.J.allFinite() && e.C_t.allFinite() && e.gamma.allFinite())) return false;
            VelocityConstraintEval ve;
            ve.resize(j.joint->velocity_rows(), nvb * static_cast<int>(j.bodies.size()));
            if (ve.b.size()) j.joint->evaluate_velocity(poses.view(j.bodies, s.t), ve);
            if (!(ve.A.allFinite() && ve.b.allFinite() && ve.gamma.allFinite())) return false;
        }
        for (const ForceInstance& f : model.forces) {
            Eigen::VectorXd Q = Eigen::VectorXd::Zero(nvb * static_cast<int>(f.bodies.size()));
            f.force->evaluate(poses.view(f.bodies, s.t), Q);
            if (!Q.allFinite()) return false;
        }
    }
    return true;
}

struct Verdict {
    int checked = 0;
    int failed = 0;
};

void report(const std::string& what, const DerivativeErrors& e, double tolerance, bool degenerate_ok, Verdict& v) {
    ++v.checked;
    struct Item {
        const char* name;
        double value;
    };
    const Item items[] = {{"Jacobian dC/dq (joints) or dQ/dq (forces)", e.jacobian},
                          {"gamma (Cddot = J vdot - gamma)", e.gamma},
                          {"C_t (Cdot = J v + C_t)", e.time_derivative},
                          {"coordinate gradient J_s", e.coordinate_jacobian},
                          {"coordinate gamma_s", e.coordinate_gamma},
                          {"(d gamma / d v)^T w (gamma_velocity_transpose)", e.gamma_velocity_transpose},
                          {"gamma_v (d/dt(A v - b) = A vdot - gamma_v)", e.velocity_gamma},
                          {"velocity rows' A, b independent of v", e.velocity_dependence},
                          {"dQ/dv", e.velocity_jacobian},
                          {"Q = -dV/dq", e.potential},
                          {"event gradient G = dg/dq", e.event_gradient},
                          {"Q affine in the load (evaluate_at_load)", e.load_affinity}};
    bool ok = e.finite && degenerate_ok;
    for (const Item& item : items) ok = ok && item.value <= tolerance;
    std::printf("%-5s %s\n", ok ? "PASS" : "FAIL", what.c_str());
    for (const Item& item : items) {
        const bool bad = item.value > tolerance;
        if (bad || item.value > 0) std::printf("        %-44s %.2e%s\n", item.name, item.value, bad ? "  <-- exceeds tolerance" : "");
    }
    if (!e.finite) std::printf("        non-finite output at a random state\n");
    if (!degenerate_ok) std::printf("        non-finite output on degenerate input (bodies at the origin, at rest or moving fast)\n");
    if (!ok) {
        std::printf("        state showing it: %s\n", e.worst_state.c_str());
        ++v.failed;
    }
}

int run_check(const CheckOptions& o) {
    namespace fs = std::filesystem;
    const fs::path library = fs::canonical(o.library);
    Registry registry({library.parent_path()});
    for (const std::string& problem : registry.problems())
        if (problem.find(library.string()) != std::string::npos || problem.find(o.library) != std::string::npos) {
            std::printf("FAIL  %s\n", problem.c_str());
            return 1;
        }
    std::vector<PluginType> mine;
    for (const PluginType& t : registry.types())
        if (fs::equivalent(t.library, library)) mine.push_back(t);
    if (mine.empty()) {
        std::printf("FAIL  %s exports no mbd plugin type (register types with MBD_JOINT_PLUGIN or MBD_FORCE_PLUGIN)\n",
                    library.c_str());
        return 1;
    }
    std::printf("library %s: ABI %d (host %d), version %s; random geometry and states from seed %u\n",
                library.c_str(), mine.front().abi, MBD_ABI_VERSION, mine.front().version.c_str(), o.seed);

    Verdict verdict;
    std::mt19937 rng(o.seed);
    for (const PluginType& t : mine) {
        if (t.kind != "joint" && t.kind != "force") {
            std::printf("skip  %s '%s': only joint and force plugins are checked\n", t.kind.c_str(), t.type.c_str());
            continue;
        }
        int dimensions_checked = 0;
        std::string last_error;
        for (Dimension d : {Dimension::Planar, Dimension::Spatial}) {
            const std::string tag = t.kind + " '" + t.type + "' (" + to_string(d) + ")";
            std::vector<std::string> scenes;
            if (t.kind == "joint") {
                for (bool with_points : {true, false})
                    scenes.push_back(with_random_joint_geometry(joint_scene(d, t.type, o.params, with_points), rng));
            } else {
                scenes.push_back(force_scene(d, t.type, o.params, true, rng));
                scenes.push_back(force_scene(d, t.type, o.params, false, rng));
            }
            bool loaded = false;
            for (const std::string& text : scenes) {
                Model model;
                try {
                    model = load_scene_text(text, "plugin-check.yaml", registry);
                } catch (const InputError& e) {
                    last_error = e.what();
                    continue;
                }
                loaded = true;
                ++dimensions_checked;
                // an element's own exception is reported here, while its library is still loaded
                // (its message and destructor live there)
                try {
                    const bool degenerate_ok = finite_on_degenerate_input(model);
                    if (t.kind == "joint") {
                        for (const JointInstance& j : model.joints)
                            report(tag + ", joint '" + j.name + "' [" + model.body_name(j.bodies[0]) + ", " +
                                       model.body_name(j.bodies[1]) + "]",
                                   check_joint_derivatives(model, j, rng), o.tolerance, degenerate_ok, verdict);
                    } else {
                        for (const ForceInstance& f : model.forces)
                            if (f.type == t.type)
                                report(tag, check_force_derivatives(model, f, rng), o.tolerance, degenerate_ok, verdict);
                    }
                } catch (const std::exception& e) {
                    std::printf("FAIL  %s: %s\n", tag.c_str(), e.what());
                    ++verdict.failed;
                }
                break;
            }
            if (!loaded) std::printf("note  %s not checked: %s\n", tag.c_str(), last_error.c_str());
        }
        if (dimensions_checked == 0) {
            std::printf("FAIL  %s '%s' could not be created in a planar or a spatial test scene; if it needs keys, "
                        "pass them with --params 'key: value' (last error: %s)\n",
                        t.kind.c_str(), t.type.c_str(), last_error.c_str());
            ++verdict.failed;
        }
    }
    std::printf("%d checked, %d failed\n", verdict.checked, verdict.failed);
    return verdict.failed == 0 ? 0 : 1;
}

}  // namespace

void add_plugin_check_command(CLI::App& app, Commands& commands) {
    CLI::App* plugin = app.add_subcommand("plugin", "Work with one plugin library");
    plugin->require_subcommand(1);
    CLI::App* check = plugin->add_subcommand(
        "check", "Validate a joint or force plugin: ABI, Jacobians and gamma against finite differences, "
                 "degenerate input");
    auto options = std::make_shared<CheckOptions>();
    check->add_option("LIBRARY", options->library, "The plugin library (.so)")->required()->check(CLI::ExistingFile);
    check->add_option("--params", options->params,
                      "A YAML key the element needs, e.g. --params 'ratio: 2' (repeat for more keys)");
    check->add_option("--tolerance", options->tolerance, "Largest relative error accepted (default 1e-6)");
    check->add_option("--seed", options->seed, "Seed of the random joint geometry and states (default 20261121)");
    commands[plugin] = [options] { return run_check(*options); };
}

}  // namespace mbd::cli
