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
//    (the default 1e-6 m/s when neither gives one);
//  - rolling resistance: the smaller of the two `rolling_resistance` coefficients mu_r (0 when a
//    material gives none), acting with the pair's effective radius R* = 1 / (1/R_i + 1/R_j)
//    (rolling_torque below; none between two flat faces);
//  - impacts (`impact: {restitution: e, rest_velocity: v}`, the ImpactLaw below): the pair is
//    rigid at touch-down when either material gives one, with the smaller restitution and the
//    larger rest velocity of those given (collision_impacts.hpp).
#pragma once

#include <mbd/sdk/contact.hpp>

#include <string>

namespace mbd::collision {

// Newton's impact law of a material (`impact:`): the contact closes by an event-located impulse
// giving the normal relative velocity -e times its value before; a rebound slower than
// rest_velocity ends at rest, and the compliant law then holds the contact.
struct ImpactLaw {
    bool given = false;
    double restitution = 0.0;     // e in [0, 1]
    double rest_velocity = 1e-3;  // m/s, > 0
};

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
    double rolling_resistance = 0.0;  // mu_r (dimensionless), 0: none
    ImpactLaw impact;
};

// The material under `node` (a map of the law's keys); `owner` names the shape in messages.
Material read_material(const Param& node, const std::string& owner, bool ground);

struct PairLaw {
    contact::NormalLaw normal;
    friction::CoulombLaw friction;
    double rolling_resistance = 0.0;  // mu_r
    double rolling_radius = 0.0;      // R*, m (infinite between flat faces)
};

// The law of two shapes' materials at their contact; `radius_i`, `radius_j` are the shapes'
// radii of curvature there (infinity for a flat face), which a Hertz material needs.
PairLaw pair_law(const Material& i, double radius_i, const Material& j, double radius_j);

// Rolling resistance: the torque on body j (world) of a contact with normal n (unit, from i
// toward j) carrying the normal force F_n >= 0, when body j rolls on body i with the relative
// angular velocity w (world, w_j - w_i). Its rolling part w_r = w - (w . n) n (spin about the
// normal is not rolling) meets the torque M = -mu_r R* F_n w_r / |w_r|, regularised as the
// friction law is: M = -mu_r R* F_n phi(|v_r|) v_r / |v_r|, with v_r = R* w_r the rolling
// velocity and phi the stiction ramp of the pair's friction law with both coefficients 1, so it
// rises smoothly from 0 at rest to its full value at the stiction velocity and stays there (a
// constant resistance, no viscous term). Zero when mu_r is 0 or R* is infinite.
Vec3 rolling_torque(const PairLaw& law, const Vec3& n, double normal_force, const Vec3& w);

}  // namespace mbd::collision
