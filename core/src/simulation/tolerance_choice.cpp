// The integration tolerance a scene needs (tolerance_choice.hpp).
#include <mbd/tolerance_choice.hpp>

#include <mbd/contact_scales.hpp>
#include <mbd/integrator.hpp>
#include <mbd/scene_document.hpp>
#include <mbd/sdk/coulomb_law.hpp>
#include <mbd/sdk/text.hpp>

#include <algorithm>
#include <functional>

namespace mbd {

namespace {

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
        const Param* node = scene_element_node(model, "forces", f.name);
        const bool friction = (f.force && f.force->is_friction()) || number_or(node, "static_friction", 0.0) > 0.0;
        if (!friction) continue;
        const double velocity = number_or(node, "stiction_velocity", friction::CoulombLaw{}.stiction_velocity);
        if (velocity > 0.0) scales.push_back({f.name, velocity, tolerance_resolving(velocity)});
    }
    return scales;
}

namespace {

// What one element's scale needs of the tolerance, for the choice and the warnings.
struct ToleranceNeed {
    std::string element;
    double tolerance = 0.0;  // the largest that resolves the scale
    std::string scale;       // "stiction velocity 1e-09", "a penetration of 7.3e-06 m at rest under ..."
    std::string rule;        // why the tolerance follows from it
    std::string error;       // the error a tolerance tol allows there, as a function of tol
    std::function<double(double)> error_at;
};

std::vector<ToleranceNeed> tolerance_needs(const Model& model) {
    std::vector<ToleranceNeed> needs;
    for (const VelocityScale& s : velocity_scales(model))
        needs.push_back({s.element, s.tolerance, "stiction velocity " + format_number(s.velocity),
                         "velocity errors tol (1 + v_s) must stay below v_s / " + format_number(kVelocityResolution) +
                             " for it to stick",
                         "velocity errors up to tol (1 + v_s)", [v = s.velocity](double tol) { return tol * (1.0 + v); }});
    for (const ContactScale& s : contact_scales(model))
        needs.push_back({s.element, s.tolerance,
                         "a penetration of " + format_number(s.penetration, 3) + " m " + s.penetration_source,
                         "position errors tol (1 + L) must stay below the penetration / " +
                             format_number(kPenetrationResolution) + " (L = " + format_number(s.extent, 3) +
                             " m, its bodies' largest coordinate) for the contact force to be right",
                         "position errors up to tol (1 + L)", [L = s.extent](double tol) { return tol * (1.0 + L); }});
    return needs;
}

}  // namespace

ToleranceChoice automatic_tolerance(const Model& model, double fallback) {
    const std::vector<ToleranceNeed> needs = tolerance_needs(model);
    const auto finest = std::min_element(needs.begin(), needs.end(), [](const ToleranceNeed& a, const ToleranceNeed& b) {
        return a.tolerance < b.tolerance;
    });
    if (finest == needs.end() || finest->tolerance >= fallback)
        return {fallback, needs.empty() ? "the default: no element holds a scale it must resolve"
                                        : "the default resolves every element's scale (stiction velocities: tol (1 + "
                                          "v_s) <= v_s / " + format_number(kVelocityResolution) +
                                          "; contact penetrations: tol (1 + L) <= delta / " +
                                          format_number(kPenetrationResolution) + ")"};
    const double tolerance = std::max(finest->tolerance, kSmallestTolerance);
    std::string reason = "force '" + finest->element + "' has " + finest->scale + ": " + finest->rule;
    if (tolerance > finest->tolerance)
        reason += "; it needs " + format_number(finest->tolerance, 3) + ", below the smallest tolerance " +
                  format_number(kSmallestTolerance) + ": it cannot be resolved, change the element's scale";
    return {tolerance, reason};
}

std::vector<std::string> tolerance_warnings(const Model& model, double tolerance) {
    std::vector<std::string> warnings;
    for (const ToleranceNeed& n : tolerance_needs(model)) {
        if (tolerance <= kToleranceSlack * n.tolerance) continue;
        warnings.push_back("force '" + n.element + "' has " + n.scale + ", which the tolerance " +
                           format_number(tolerance) + " cannot resolve: " + n.error + " = " +
                           format_number(n.error_at(tolerance), 3) + " hide it (" + n.rule +
                           "); it needs a tolerance of at most " + format_number(n.tolerance, 3) +
                           ", or leave the tolerance to the automatic choice");
    }
    return warnings;
}

}  // namespace mbd
