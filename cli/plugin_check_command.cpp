// `mbd plugin check [LIB.so | TYPE]`: load a joint or force plugin library (or the library
// of one type, or of every type in the plugin folders) and validate every type it provides: its ABI, its Jacobians and gamma (and a joint's
// driver coordinate) against finite differences on random states, force
// Jacobians and Q = -dV/dq, and finite output on degenerate input. The joint
// geometry is random too (seeded by --seed): a random joint point, so the marker
// offsets from the mass centres are non-zero, random axes, and random `points`
// (one per body) when the joint accepts that key. The other keys come from the type's own
// description (mbd/sdk/plugin_keys.hpp: the examples of its required keys; two moving bodies
// for a two-body element), so every described type is checked with no flags. Each
// failure is printed with the state that shows it; the exit status says pass
// (0) or fail (1).
#include "commands.hpp"
#include "plugin_check_scenes.hpp"

#include <mbd/body_poses.hpp>
#include <mbd/derivative_check.hpp>
#include <mbd/plugin_description.hpp>
#include <mbd/registry.hpp>
#include <mbd/scene.hpp>
#include <mbd/sdk/domain_error.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <random>
#include <sstream>

namespace mbd::cli {
namespace {

struct CheckOptions {
    std::string target;  // a library file, a type name, or empty: every joint and force type
    std::vector<std::string> params;  // extra YAML keys for the element, e.g. "ratio: 2", one per entry
    double tolerance = 1e-6;
    unsigned seed = 20261121;
};

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

// The scenes a type is tried in, in one dimension: from its description when it has one,
// otherwise every variant (with and without points; two bodies, then one).
std::vector<std::string> test_scenes(const PluginType& t, const PluginDescription* description, Dimension d,
                                     const std::vector<std::string>& params, std::mt19937& rng) {
    const std::vector<std::string> keys = element_keys(description, d, params);
    std::vector<std::string> scenes;
    if (t.kind == "joint") {
        for (bool with_points : {true, false})
            if (!description || !with_points)
                scenes.push_back(with_random_joint_geometry(joint_scene(d, t.type, keys, with_points), rng));
    } else if (description) {
        scenes.push_back(force_scene(d, t.type, keys, description->bodies != kOneBody, rng));
    } else {
        scenes.push_back(force_scene(d, t.type, keys, true, rng));
        scenes.push_back(force_scene(d, t.type, keys, false, rng));
    }
    return scenes;
}

// Load the first of `scenes` that loads and check its elements of type `t`; false when none loads.
bool check_in_scenes(const PluginType& t, const std::string& tag, const std::vector<std::string>& scenes,
                     const CheckOptions& o, Registry& registry, std::mt19937& rng, Verdict& verdict,
                     std::string& last_error) {
    for (const std::string& text : scenes) {
        Model model;
        try {
            model = load_scene_text(text, "plugin-check.yaml", registry);
        } catch (const InputError& e) {
            last_error = e.what();
            continue;
        }
        // an element's own exception is reported here, while its library is still loaded (its
        // message and destructor live there)
        try {
            const bool degenerate_ok = finite_on_degenerate_input(model);
            if (t.kind == "joint") {
                for (const JointInstance& j : model.joints)
                    report(tag + ", joint '" + j.name + "' [" + model.body_name(j.bodies[0]) + ", " +
                               model.body_name(j.bodies[1]) + "]",
                           check_joint_derivatives(model, j, rng), o.tolerance, degenerate_ok, verdict);
            } else {
                for (const ForceInstance& f : model.forces) {
                    if (f.type != t.type) continue;
                    std::string bodies;
                    for (int b : f.bodies) bodies += (bodies.empty() ? "" : ", ") + model.body_name(b);
                    report(tag + " [" + bodies + "]", check_force_derivatives(model, f, rng), o.tolerance,
                           degenerate_ok, verdict);
                }
            }
        } catch (const std::exception& e) {
            std::printf("FAIL  %s: %s\n", tag.c_str(), e.what());
            ++verdict.failed;
        }
        return true;
    }
    return false;
}

void check_type(const PluginType& t, const CheckOptions& o, Registry& registry, std::mt19937& rng, Verdict& verdict) {
    if (t.kind != "joint" && t.kind != "force") {
        std::printf("skip  %s '%s': only joint and force plugins are checked\n", t.kind.c_str(), t.type.c_str());
        return;
    }
    const PluginDescription* description = plugin_description(registry, t.kind, t.type);
    int dimensions_checked = 0;
    std::string last_error;
    for (Dimension d : {Dimension::Planar, Dimension::Spatial}) {
        const std::string tag = t.kind + " '" + t.type + "' (" + to_string(d) + ")";
        const int bit = d == Dimension::Planar ? kPlanarOnly : kSpatialOnly;
        if (description && !(description->dimensions & bit)) continue;
        if (check_in_scenes(t, tag, test_scenes(t, description, d, o.params, rng), o, registry, rng, verdict,
                            last_error)) {
            ++dimensions_checked;
        } else if (description && o.params.empty()) {
            // the type says it works here with these keys: a scene that does not load is a fault
            std::printf("FAIL  %s: its test scene, built from the type's key description, does not load: %s\n",
                        tag.c_str(), last_error.c_str());
            ++verdict.failed;
        } else {
            // --params may suit one dimension only (a vector's size)
            std::printf("note  %s not checked: %s\n", tag.c_str(), last_error.c_str());
        }
    }
    if (dimensions_checked == 0 && (!description || !o.params.empty())) {
        std::printf("FAIL  %s '%s' could not be created in a planar or a spatial test scene; %s (last error: %s)\n",
                    t.kind.c_str(), t.type.c_str(),
                    description ? "check the keys given with --params"
                                : "it describes no keys (MBD_JOINT_KEYS / MBD_FORCE_KEYS, docs/plugin-sdk.md), so pass "
                                  "the keys it needs with --params 'key: value'",
                    last_error.c_str());
        ++verdict.failed;
    }
}

// The types to check and the registry that finds them: a library file's types (its folder
// searched alone), one type of the plugin folders by name, or every joint and force type there.
std::vector<PluginType> types_to_check(const CheckOptions& o, std::unique_ptr<Registry>& registry, int& status) {
    namespace fs = std::filesystem;
    std::vector<PluginType> mine;
    std::error_code ec;
    if (!o.target.empty() && fs::is_regular_file(o.target, ec)) {
        const fs::path library = fs::canonical(o.target);
        registry = std::make_unique<Registry>(std::vector<fs::path>{library.parent_path()});
        for (const std::string& problem : registry->problems())
            if (problem.find(library.string()) != std::string::npos || problem.find(o.target) != std::string::npos) {
                std::printf("FAIL  %s\n", problem.c_str());
                status = 1;
                return {};
            }
        for (const PluginType& t : registry->types())
            if (fs::equivalent(t.library, library)) mine.push_back(t);
        if (mine.empty()) {
            std::printf("FAIL  %s exports no mbd plugin type (register types with MBD_JOINT_PLUGIN or "
                        "MBD_FORCE_PLUGIN)\n", library.c_str());
            status = 1;
        }
        return mine;
    }
    registry = std::make_unique<Registry>();
    for (const PluginType& t : registry->types())
        if ((t.kind == "joint" || t.kind == "force") && t.abi == MBD_ABI_VERSION &&
            (o.target.empty() || t.type == o.target))
            mine.push_back(t);
    std::sort(mine.begin(), mine.end(), [](const PluginType& a, const PluginType& b) {
        return a.kind != b.kind ? a.kind < b.kind : a.type < b.type;
    });
    if (mine.empty()) {
        std::vector<std::string> known = registry->type_names("joint");
        for (const std::string& f : registry->type_names("force")) known.push_back(f);
        std::string list;
        for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
        std::printf("FAIL  '%s' is neither a plugin library file nor a joint or force type of the plugin folders "
                    "(mbd plugins lists them); known types: %s\n", o.target.c_str(), list.empty() ? "(none)" : list.c_str());
        status = 1;
    }
    return mine;
}

int run_check(const CheckOptions& o) {
    std::unique_ptr<Registry> registry;
    int status = 0;
    const std::vector<PluginType> mine = types_to_check(o, registry, status);
    if (mine.empty()) return status == 0 ? 1 : status;

    std::printf("random geometry and states from seed %u\n", o.seed);
    Verdict verdict;
    std::mt19937 rng(o.seed);
    std::string library;
    for (const PluginType& t : mine) {
        if (t.library.string() != library) {
            library = t.library.string();
            std::printf("library %s: ABI %d (host %d), version %s\n", library.c_str(), t.abi, host_abi(t.kind),
                        t.version.c_str());
        }
        check_type(t, o, *registry, rng, verdict);
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
    check->add_option("TARGET", options->target,
                      "A plugin library (.so), or a joint or force type of the plugin folders (e.g. screw); "
                      "none: every joint and force type there");
    check->add_option("--params", options->params,
                      "A YAML key for the element, e.g. --params 'ratio: 2' (repeat for more keys); it replaces the "
                      "example the type's key description gives");
    check->add_option("--tolerance", options->tolerance, "Largest relative error accepted (default 1e-6)");
    check->add_option("--seed", options->seed, "Seed of the random joint geometry and states (default 20261121)");
    commands[plugin] = [options] { return run_check(*options); };
}

}  // namespace mbd::cli
