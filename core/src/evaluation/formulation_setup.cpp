// Reading and checking a formulation's keys (formulation_setup.hpp).
#include <mbd/formulation_setup.hpp>

#include <mbd/integrator.hpp>
#include <mbd/linear_algebra.hpp>
#include <mbd/sdk/suggest.hpp>

#include <vector>

namespace mbd {

namespace {

struct NamedStabilization {
    const char* name;
    Stabilization value;
};
const NamedStabilization kStabilizations[] = {
    {"projection", Stabilization::Projection},
    {"baumgarte", Stabilization::Baumgarte},
    {"none", Stabilization::None},
};

std::string stabilization_choices() {
    const std::vector<std::string> names = stabilization_names();
    std::string list;
    for (size_t i = 0; i < names.size(); ++i) list += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
    return list;
}

}  // namespace

std::vector<std::string> stabilization_names() {
    std::vector<std::string> names;
    for (const NamedStabilization& s : kStabilizations) names.emplace_back(s.name);
    return names;
}

Stabilization parse_stabilization(const std::string& name) {
    for (const NamedStabilization& s : kStabilizations)
        if (name == s.name) return s.value;
    throw InputError("", "'stabilization' must be " + stabilization_choices() + ", got '" + name + "'");
}

namespace {

// One shared key: its group and how it is read into the options.
struct SharedKey {
    const char* name;
    OptionGroup group;
    void (*read)(const Params& params, FormulationOptions& options);
};

Stabilization stabilization_value(const Param& p) {
    try {
        return parse_stabilization(p.text);
    } catch (const InputError& e) {
        p.fail(e.message());
    }
}

LinearAlgebra algebra_value(const Param& p) {
    try {
        return parse_linear_algebra(p.text);
    } catch (const InputError&) {
        p.fail("'linear_algebra' must be auto, dense or sparse, got '" + p.text + "'");
    }
}

bool boolean_value(const Param& p, const char* key) {
    if (p.is_scalar() && (p.text == "true" || p.text == "false")) return p.text == "true";
    p.fail("'" + std::string(key) + "' must be true or false");
}

// In the order the keys are listed to the user.
const SharedKey kSharedKeys[] = {
    {"stabilization", kStabilizationOptions,
     [](const Params& p, FormulationOptions& o) { o.stabilization = stabilization_value(p.at("stabilization")); }},
    {"alpha", kStabilizationOptions,
     [](const Params& p, FormulationOptions& o) { o.baumgarte_alpha = p.non_negative("alpha", 0.0); }},
    {"beta", kStabilizationOptions, [](const Params& p, FormulationOptions& o) { o.baumgarte_beta = p.number("beta"); }},
    {"projection_tolerance", kStabilizationOptions,
     [](const Params& p, FormulationOptions& o) { o.projection_tolerance = p.positive("projection_tolerance"); }},
    {"linear_algebra", kLinearAlgebraOptions,
     [](const Params& p, FormulationOptions& o) { o.algebra = algebra_value(p.at("linear_algebra")); }},
    {"sparse_threshold", kLinearAlgebraOptions,
     [](const Params& p, FormulationOptions& o) {
         o.sparse_threshold = static_cast<int>(p.integer("sparse_threshold", 1, 1000000000));
     }},
    {"pivot_threshold", kPartitionOptions,
     [](const Params& p, FormulationOptions& o) {
         o.partition.pivot_threshold = p.positive("pivot_threshold");
         if (o.partition.pivot_threshold > 1.0) p.at("pivot_threshold").fail("'pivot_threshold' must be in (0, 1]");
     }},
    {"reselect_ratio", kPartitionOptions,
     [](const Params& p, FormulationOptions& o) { o.partition.reselect_ratio = p.non_negative("reselect_ratio", 0.05); }},
    {"rank_tolerance", kPartitionOptions,
     [](const Params& p, FormulationOptions& o) { o.partition.rank_tolerance = p.positive("rank_tolerance"); }},
    {"log", kPartitionOptions,
     [](const Params& p, FormulationOptions& o) { o.log_choices = boolean_value(p.at("log"), "log"); }},
    {"newton_tolerance", kNewtonOptions,
     [](const Params& p, FormulationOptions& o) { o.newton.tolerance = p.positive("newton_tolerance"); }},
    {"newton_iterations", kNewtonOptions,
     [](const Params& p, FormulationOptions& o) {
         o.newton.iterations = static_cast<int>(p.integer("newton_iterations", 1, 1000000));
     }},
    {"singularity_tolerance", kSingularityOptions,
     [](const Params& p, FormulationOptions& o) {
         o.singularity_tolerance = p.non_negative("singularity_tolerance", 0.0);
         if (o.singularity_tolerance >= 1.0)
             p.at("singularity_tolerance").fail("'singularity_tolerance' must be in [0, 1) (0: no check)");
     }},
};

// `formulation: NAME` as a map holding only its type, so that both forms read alike.
Param as_map(const Param& node) {
    if (node.is_map()) return node;
    Param map;
    map.kind = Param::Kind::Map;
    map.file = node.file;
    map.line = node.line;
    map.fields["type"] = node;
    return map;
}

// An element of the scene the chosen pair must handle: refused, naming `element`, when the
// formulation does not (`formulation_remedy` says what to do) or the integrator solves the index-3
// equations (`integrator_remedy`).
// The integrators that work through the formulation (no index-3 form): "euler, rk4, ... or cvode".
std::string through_formulation() {
    return integrator_list([](const IntegratorDescription& d) { return !d.needs_index3; });
}

void require_handled(const std::string& where, const std::string& element, bool formulation_handles,
                     const std::string& name, const std::string& formulation_remedy, bool needs_index3,
                     const std::string& integrator, const std::string& integrator_remedy) {
    if (!formulation_handles)
        throw InputError(where, element + ", which the '" + name + "' formulation " + formulation_remedy);
    if (needs_index3) throw InputError(where, element + ", which the " + integrator + " integrator " + integrator_remedy);
}

}  // namespace

FormulationOptions read_formulation_options(const Param& node) {
    const Param map = as_map(node);
    const auto type = map.fields.find("type");
    const Params params("formulation '" + (type != map.fields.end() ? type->second.text : std::string()) + "'", &map);
    FormulationOptions options;
    for (const SharedKey& key : kSharedKeys)
        if (params.has(key.name)) key.read(params, options);
    return options;
}

std::shared_ptr<Formulation> create_formulation(Registry& registry, const std::string& name, const Param* node,
                                                const std::string& where) {
    Param map;
    map.kind = Param::Kind::Map;
    if (node) map = as_map(*node);
    FormulationSpec spec{name, name, Params("formulation '" + name + "'", &map)};
    std::shared_ptr<Formulation> formulation = registry.create_formulation(spec, where);

    // the keys the plugin read of its own, then the shared keys it honours
    std::vector<std::string> keys{"type"};
    for (const std::string& own : spec.params.asked_keys())
        if (own != "type") keys.push_back(own);
    spec.params.mark_read("type");
    for (const SharedKey& key : kSharedKeys) {
        if (!(formulation->options_used() & key.group)) continue;
        keys.push_back(key.name);
        spec.params.mark_read(key.name);
    }
    const std::vector<std::string> unread = spec.params.unread_keys();
    if (unread.empty()) return formulation;

    const std::string& bad = unread.front();
    std::string message = "formulation '" + name + "': unknown key '" + bad + "'";
    bool shared = false;
    for (const SharedKey& key : kSharedKeys) shared = shared || bad == key.name;
    const std::string near = nearest_name(bad, keys);
    if (shared)
        message += " (the " + name + " formulation does not use it).";
    else if (!near.empty())
        message += "; did you mean '" + near + "'?";
    else
        message += ".";
    std::string list;
    for (const std::string& k : keys) list += (list.empty() ? "" : ", ") + k;
    throw InputError(map.fields.at(bad).location(), message + " Its keys are " + list);
}

void require_velocity_rows_handled(const Model& model, const Formulation& formulation, const std::string& name,
                                   bool needs_index3, const std::string& integrator) {
    for (const JointInstance& j : model.joints) {
        if (j.joint->velocity_rows() == 0) continue;
        const std::string joint = "joint '" + j.name + "' (type " + j.type + ") has " +
                                  std::to_string(j.joint->velocity_rows()) +
                                  " velocity-level (nonholonomic) constraint row(s)";
        require_handled(j.where, joint, formulation.supports_velocity_constraints(), name,
                        "does not handle; use the augmented or the embedding formulation (--formulation augmented, "
                        "or `formulation: augmented` in the scene; docs/formulations.md)",
                        needs_index3, integrator,
                        "does not handle (it solves the index-3 equations of the holonomic rows only); use " +
                            through_formulation());
        return;
    }
}

void require_reaction_loads_handled(const Model& model, const Formulation& formulation, const std::string& name,
                                    bool needs_index3, const std::string& integrator) {
    for (const ForceInstance& f : model.forces) {
        if (f.load_joint < 0) continue;
        const std::string force = "force '" + f.name + "' (type " + f.type + ") takes its load from the reaction of joint '" +
                                  model.joints[f.load_joint].name + "'";
        require_handled(f.where, force, formulation.supports_reaction_loads(), name,
                        "does not solve with its multipliers; use the augmented formulation (--formulation "
                        "augmented, or `formulation: augmented` in the scene; docs/formulations.md)",
                        needs_index3, integrator,
                        "does not solve (it works on the index-3 equations directly); use " + through_formulation());
        return;
    }
}

void require_flexible_bodies_handled(const Model& model, const Formulation& formulation, const std::string& name,
                                     bool needs_index3, const std::string& integrator) {
    if (model.flexible_bodies.empty()) return;
    const FlexibleBodyInstance& f = model.flexible_bodies.front();
    require_handled(f.where, "flexible body '" + f.name + "' (type " + f.type + ")",
                    formulation.supports_flexible_bodies(), name,
                    "does not take (it handles rigid bodies only); use the augmented formulation (--formulation "
                    "augmented, or `formulation: augmented` in the scene; docs/formulations.md)",
                    needs_index3, integrator,
                    "does not take (its index-3 equations are not mapped through the material frames); use " +
                        through_formulation());
}

}  // namespace mbd
