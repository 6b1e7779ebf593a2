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
                                 "'; a material takes stiffness, exponent, damping or restitution with "
                                 "impact_velocity and restitution_model, static_friction, kinetic_friction, "
                                 "stiction_velocity");
}

}  // namespace

Material read_material(const Param& node, const std::string& owner, bool ground) {
    if (!node.is_map()) node.fail(owner + ": 'material' must be a map of keys (stiffness, exponent, restitution, ...)");
    Material m;
    read_for(node, owner, [&](const ForceSpec& spec) {
        if (spec.params.has("stiffness")) {
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
        refuse_unread(spec.params, node, owner);
        return 0;
    });
    return m;
}

PairLaw pair_law(const Material& i, const Material& j) {
    PairLaw law;
    const Material* compliant[2] = {i.rigid ? nullptr : &i, j.rigid ? nullptr : &j};
    const double n = compliant[0] ? i.normal.exponent : j.normal.exponent;
    double compliance = 0.0, alpha_weighted = 0.0;  // sum of k^(-1/n), and of alpha k^(-1/n)
    for (const Material* m : compliant) {
        if (!m) continue;
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
    return law;
}

}  // namespace mbd::collision
