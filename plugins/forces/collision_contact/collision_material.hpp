// The contact material of a collision shape and the law of a pair of shapes.
//
// A shape's material takes the keys of the two-body contact elements (mbd/sdk/contact.hpp,
// read by the same functions): stiffness k and exponent n of the Hunt-Crossley law, damping c or
// restitution e at an impact velocity (Lankarani-Nikravesh or Hunt-Crossley), static and kinetic
// friction and the stiction velocity. A ground shape may leave out the normal law (no
// stiffness): it is then rigid, and its friction keys alone count.
//
// A pair of shapes (docs/scene-format.md "Collision shapes", the rules):
//  - the two materials act in series: each is compressed by delta_i with F = k_i delta_i^n, so
//    F = k delta^n with k^(-1/n) = k_i^(-1/n) + k_j^(-1/n) (a rigid one adds nothing); both
//    compliant materials must have the same exponent n;
//  - the damping per unit stiffness alpha = c / k (the Hunt-Crossley alpha, which alone sets the
//    restitution of an impact at a given speed) is the compliance-weighted mean of the two, so a
//    pair of one material, or a material against a rigid ground, keeps its own alpha exactly;
//  - friction: the smaller of each coefficient, and the smaller stiction velocity of those given
//    (the default 1e-6 m/s when neither gives one).
#pragma once

#include <mbd/sdk/contact.hpp>

#include <string>

namespace mbd::collision {

struct Material {
    bool rigid = false;           // a ground material without a normal law
    contact::NormalLaw normal;    // stiffness, exponent, damping (unused when rigid)
    friction::CoulombLaw friction;
    bool stiction_given = false;  // the stiction velocity was given (not the default)
};

// The material under `node` (a map of the law's keys); `owner` names the shape in messages.
Material read_material(const Param& node, const std::string& owner, bool ground);

struct PairLaw {
    contact::NormalLaw normal;
    friction::CoulombLaw friction;
};

PairLaw pair_law(const Material& i, const Material& j);

}  // namespace mbd::collision
