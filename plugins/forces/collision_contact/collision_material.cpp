#include "collision_material.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mbd::collision {

namespace {

// The contact law's readers take a force element (mbd/sdk/contact.hpp) and name it in their
// messages as "force 'NAME': "; a material is no element, so its messages name the shape.
constexpr const char* kElement = "collision_contact";

template <class Read>
auto read_for(const Param& node, const std::string& owner, Read&& read) {
    ForceSpec spec;
    spec.name = kElement;
    spec.type = kElement;
    spec.dimension = Dimension::Spatial;
    spec.params = Params(owner, &node);
    try {
        return read(spec);
    } catch (const InputError& e) {
        std::string message = e.message();
        const std::string prefix = std::string("force '") + kElement + "': ";
        if (message.rfind(prefix, 0) == 0) message.erase(0, prefix.size());
        throw InputError(e.where(), owner + " material: " + message);
    }
}

void refuse_unread(const Params& params, const Param& node, const std::string& owner) {
    for (const std::string& key : params.unread_keys())
        node.fields.at(key).fail(owner + " material: unknown key '" + key +
                                 "'; a material takes stiffness and exponent (or young_modulus and poisson_ratio), damping or "
                                 "restitution with "
                                 "impact_velocity and restitution_model, static_friction, kinetic_friction, "
                                 "stiction_velocity, rolling_resistance, impact");
}

// `impact: {restitution: e, rest_velocity: v}` (Newton's law at an event-located touch-down).
ImpactLaw read_impact(const Param& node) {
    if (!node.is_map())
        node.fail("'impact' must be a map: {restitution: e, rest_velocity: v} (Newton's law at touch-down)");
    for (const auto& field : node.fields)
        if (field.first != "restitution" && field.first != "rest_velocity")
            field.second.fail("unknown key 'impact." + field.first + "'; 'impact' takes restitution and rest_velocity");
    ImpactLaw law;
    law.given = true;
    const auto e = node.fields.find("restitution");
    if (e == node.fields.end())
        node.fail("'impact' needs 'restitution' e (0 <= e <= 1): the normal velocity after a touch-down is -e "
                  "times its value before");
    law.restitution = e->second.as_number("restitution");
    if (!(law.restitution >= 0.0 && law.restitution <= 1.0))
        e->second.fail("'impact.restitution' must lie in [0, 1] (0: plastic, 1: elastic), got " + e->second.text);
    const auto v = node.fields.find("rest_velocity");
    if (v != node.fields.end()) {
        law.rest_velocity = v->second.as_number("rest_velocity");
        if (!(law.rest_velocity > 0.0))
            v->second.fail("'impact.rest_velocity' must be positive (m/s: the rebound speed below which the contact "
                           "comes to rest), got " + v->second.text);
    }
    return law;
}

// young_modulus E (> 0) and poisson_ratio nu (0 <= nu < 0.5); the damping keys read by the
// shared reader as for a unit stiffness, so normal.damping is alpha = c / k.
void read_hertz(const ForceSpec& spec, const Param& node, Material& m) {
    for (const char* key : {"stiffness", "exponent"})
        if (spec.params.has(key))
            force_support::fail(spec, std::string("give either 'young_modulus' with 'poisson_ratio' (Hertz: n = 1.5) "
                                                  "or '") + key + "', not both", &spec.params.at(key));
    const double E = force_support::number(spec, "young_modulus");
    if (!(E > 0.0))
        force_support::fail(spec, "'young_modulus' must be positive (Pa)", &spec.params.at("young_modulus"));
    if (!spec.params.has("poisson_ratio"))
        force_support::fail(spec, "'young_modulus' needs 'poisson_ratio' (0 <= nu < 0.5)");
    const double nu = force_support::number(spec, "poisson_ratio");
    if (!(nu >= 0.0 && nu < 0.5))
        force_support::fail(spec, "'poisson_ratio' must be in [0, 0.5)", &spec.params.at("poisson_ratio"));
    Param unit = node;  // the damping keys, as the law of a unit stiffness
    unit.fields.erase("young_modulus");
    unit.fields.erase("poisson_ratio");
    unit.fields["stiffness"] = node.fields.at("young_modulus");
    unit.fields["stiffness"].text = "1";
    ForceSpec as_unit = spec;
    as_unit.params = Params(spec.params.owner(), &unit);
    m.normal = contact::read_normal_law(as_unit);
    m.normal.exponent = 1.5;
    for (const std::string& key : as_unit.params.asked_keys()) spec.params.mark_read(key);
    m.hertz = true;
    m.hertz_compliance = (1.0 - nu * nu) / E;
}

}  // namespace

Material read_material(const Param& node, const std::string& owner, bool ground) {
    if (!node.is_map()) node.fail(owner + ": 'material' must be a map of keys (stiffness, exponent, restitution, ...)");
    Material m;
    read_for(node, owner, [&](const ForceSpec& spec) {
        if (spec.params.has("young_modulus")) {
            read_hertz(spec, node, m);
        } else if (spec.params.has("stiffness")) {
            m.normal = contact::read_normal_law(spec);
        } else if (ground) {
            m.rigid = true;
            for (const char* key : {"exponent", "damping", "restitution", "impact_velocity", "restitution_model"})
                if (spec.params.has(key))
                    force_support::fail(spec, std::string("'") + key + "' belongs to a normal law, which needs "
                                              "'stiffness'; without it the ground's shape is rigid (the other "
                                              "shape's law acts)", &spec.params.at(key));
        } else {
            force_support::fail(spec, "missing key 'stiffness' (k of F_n = k delta^n + c delta^n delta_dot, "
                                      "N/m^n; only a ground shape may be rigid)");
        }
        m.friction = contact::read_friction(spec);
        m.stiction_given = spec.params.has("stiction_velocity");
        m.rolling_resistance = force_support::non_negative_or(spec, "rolling_resistance", 0.0);
        if (spec.params.has("impact")) m.impact = read_impact(spec.params.at("impact"));
        refuse_unread(spec.params, node, owner);
        return 0;
    });
    return m;
}

PairLaw pair_law(const Material& i, double radius_i, const Material& j, double radius_j) {
    PairLaw law;
    const Material* compliant[2] = {i.rigid ? nullptr : &i, j.rigid ? nullptr : &j};
    const double n = compliant[0] ? i.normal.exponent : j.normal.exponent;
    // Hertz: the elastic compliances add (1/E*), then k = 4/3 E* sqrt(R*) as one term of the series
    const double root_R = std::sqrt(1.0 / (1.0 / radius_i + 1.0 / radius_j));
    double hertz = 0.0, hertz_alpha = 0.0;  // sum of (1 - nu^2) / E, and of alpha times it
    for (const Material* m : compliant)
        if (m && m->hertz) {
            hertz += m->hertz_compliance;
            hertz_alpha += m->normal.damping * m->hertz_compliance;
        }
    double compliance = 0.0, alpha_weighted = 0.0;  // sum of k^(-1/n), and of alpha k^(-1/n)
    if (hertz > 0.0) {
        const double c = std::pow(4.0 / 3.0 * root_R / hertz, -1.0 / n);
        compliance += c;
        alpha_weighted += hertz_alpha / hertz * c;
    }
    for (const Material* m : compliant) {
        if (!m || m->hertz) continue;
        const double c = std::pow(m->normal.stiffness, -1.0 / n);
        compliance += c;
        alpha_weighted += m->normal.damping / m->normal.stiffness * c;
    }
    law.normal.exponent = n;
    law.normal.stiffness = std::pow(compliance, -n);
    law.normal.damping = alpha_weighted / compliance * law.normal.stiffness;
    law.friction.mu_static = std::min(i.friction.mu_static, j.friction.mu_static);
    law.friction.mu_kinetic = std::min(i.friction.mu_kinetic, j.friction.mu_kinetic);
    if (i.stiction_given && j.stiction_given)
        law.friction.stiction_velocity = std::min(i.friction.stiction_velocity, j.friction.stiction_velocity);
    else if (i.stiction_given || j.stiction_given)
        law.friction.stiction_velocity = i.stiction_given ? i.friction.stiction_velocity : j.friction.stiction_velocity;
    law.rolling_resistance = std::min(i.rolling_resistance, j.rolling_resistance);
    law.rolling_radius = 1.0 / (1.0 / radius_i + 1.0 / radius_j);
    return law;
}

Vec3 rolling_torque(const PairLaw& law, const Vec3& n, double normal_force, const Vec3& w) {
    if (law.rolling_resistance == 0.0 || !std::isfinite(law.rolling_radius) || normal_force <= 0.0) return Vec3::Zero();
    const double R = law.rolling_radius;
    const Vec3 rolling_speed = R * (w - w.dot(n) * n);  // the rolling velocity v_r = R* w_r
    const friction::CoulombLaw ramp{1.0, 1.0, law.friction.stiction_velocity};
    // mu_r R* F_n phi(|v_r|) along -v_r / |v_r|: coefficient_per_speed is phi(|v_r|) / |v_r|
    return -law.rolling_resistance * R * normal_force * ramp.coefficient_per_speed(rolling_speed.squaredNorm()) *
           rolling_speed;
}

}  // namespace mbd::collision
