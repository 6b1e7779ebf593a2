// The integration tolerance a scene needs (tolerance_choice.hpp).
#include <mbd/tolerance_choice.hpp>

#include <mbd/integrator.hpp>
#include <mbd/sdk/coulomb_law.hpp>
#include <mbd/sdk/text.hpp>

#include <algorithm>

namespace mbd {

namespace {

// The scene node of force element `name` (null: none, e.g. the core's gravity element).
const Param* force_node(const Model& model, const std::string& name) {
    if (!model.document || !model.document->is_map()) return nullptr;
    const auto forces = model.document->fields.find("forces");
    if (forces == model.document->fields.end() || !forces->second.is_list()) return nullptr;
    for (const Param& item : forces->second.items) {
        if (!item.is_map()) continue;
        const auto key = item.fields.find("name");
        if (key != item.fields.end() && key->second.is_scalar() && key->second.text == name) return &item;
    }
    return nullptr;
}

// The number under `key` of `node`, or `fallback` when it has none (the plugin has already
// refused a value that is not a number, so this one reads).
double number_or(const Param* node, const char* key, double fallback) {
    if (!node) return fallback;
    const auto it = node->fields.find(key);
    return it == node->fields.end() ? fallback : it->second.as_number(key);
}

// A given tolerance within 1 % of the one needed is taken as it: a tolerance typed as v_s / 10
// resolves v_s, though (1 + v_s) makes the exact bound a hair smaller.
constexpr double kToleranceSlack = 1.01;

}  // namespace

double tolerance_resolving(double velocity) { return velocity / (kVelocityResolution * (1.0 + velocity)); }

std::vector<VelocityScale> velocity_scales(const Model& model) {
    std::vector<VelocityScale> scales;
    for (const ForceInstance& f : model.forces) {
        const Param* node = force_node(model, f.name);
        const bool friction = (f.force && f.force->is_friction()) || number_or(node, "static_friction", 0.0) > 0.0;
        if (!friction) continue;
        const double velocity = number_or(node, "stiction_velocity", friction::CoulombLaw{}.stiction_velocity);
        if (velocity > 0.0) scales.push_back({f.name, velocity, tolerance_resolving(velocity)});
    }
    return scales;
}

ToleranceChoice automatic_tolerance(const Model& model, double fallback) {
    const std::vector<VelocityScale> scales = velocity_scales(model);
    const auto finest = std::min_element(scales.begin(), scales.end(), [](const VelocityScale& a, const VelocityScale& b) {
        return a.tolerance < b.tolerance;
    });
    if (finest == scales.end() || finest->tolerance >= fallback)
        return {fallback, scales.empty() ? "the default: no element holds a scale it must resolve"
                                         : "the default resolves every element's stiction velocity (tol (1 + v_s) <= "
                                           "v_s / " + format_number(kVelocityResolution) + ")"};
    const double tolerance = std::max(finest->tolerance, kSmallestTolerance);
    std::string reason = "force '" + finest->element + "' has stiction velocity " + format_number(finest->velocity) +
                         ": velocity errors tol (1 + v_s) must stay below v_s / " + format_number(kVelocityResolution) +
                         " for it to stick";
    if (tolerance > finest->tolerance)
        reason += "; it needs " + format_number(finest->tolerance, 3) + ", below the smallest tolerance " +
                  format_number(kSmallestTolerance) + ": it cannot be resolved, give it a larger stiction_velocity";
    return {tolerance, reason};
}

std::vector<std::string> tolerance_warnings(const Model& model, double tolerance) {
    std::vector<std::string> warnings;
    for (const VelocityScale& s : velocity_scales(model)) {
        if (tolerance <= kToleranceSlack * s.tolerance) continue;
        warnings.push_back("force '" + s.element + "' has stiction velocity " + format_number(s.velocity) +
                           ", which the tolerance " + format_number(tolerance) +
                           " cannot resolve: velocity errors up to tol (1 + v_s) = " +
                           format_number(tolerance * (1.0 + s.velocity), 3) + " hide whether it sticks; it needs a "
                           "tolerance of at most " + format_number(s.tolerance, 3) + " (v_s / " +
                           format_number(kVelocityResolution) + " / (1 + v_s)), or leave the tolerance to the "
                           "automatic choice");
    }
    return warnings;
}

}  // namespace mbd
