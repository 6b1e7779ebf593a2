// The contact material of a collision shape and the law of a pair of shapes.
//
// A shape's material takes the keys of the two-body contact elements (mbd/sdk/contact.hpp,
// read by the same functions): stiffness k and exponent n of the Hunt-Crossley law, damping c or
// restitution e at an impact velocity (Lankarani-Nikravesh or Hunt-Crossley), static and kinetic
// friction and the stiction velocity. A ground shape may leave out the normal law (no
// stiffness): it is then rigid, and its friction keys alone count.
//
// A material may instead give `young_modulus` E and `poisson_ratio` nu (spheres and capsules: a
// curved surface): Hertz's law of two elastic bodies, k = 4/3 E* sqrt(R*), n = 1.5, with
// 1/E* = sum (1 - nu_i^2) / E_i over the Hertz materials and 1/R* = 1/R_i + 1/R_j (Johnson,
// Contact Mechanics, Eq. 4.22); against a stiffness material, the two in series as below.
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
    // Hertz: `young_modulus` E and `poisson_ratio` nu instead of stiffness: the pair's k follows
    // from its curvature (k = 4/3 E* sqrt(R*), n = 1.5); normal.stiffness is then 1 and
    // normal.damping the Hunt-Crossley alpha = c / k
    bool hertz = false;
    double hertz_compliance = 0.0;  // (1 - nu^2) / E
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

// The law of two shapes' materials at their contact; `radius_i`, `radius_j` are the shapes'
// radii of curvature there (infinity for a flat face), which a Hertz material needs.
PairLaw pair_law(const Material& i, double radius_i, const Material& j, double radius_j);

}  // namespace mbd::collision
