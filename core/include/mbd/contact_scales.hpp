// The scales a compliant contact holds (Force::compliant_law, F_n = k delta^n + damping), for the
// automatic choice (docs/user-guide.md "The automatic choice"):
//  - the penetration: at rest under the weight of the mass it carries, delta_s = (m g / k)^(1/n)
//    (the law balancing m g), and, when the damping was fitted to a restitution at an impact
//    velocity v_i, the largest penetration of that impact, delta_i = ((n + 1) m v_i^2 / (2 k))^(1/(n+1))
//    (the kinetic energy m v_i^2 / 2 stored as k delta^(n+1) / (n + 1));
//  - the frequency of the contact's oscillation about its penetration, w = sqrt(n k delta^(n-1) / m)
//    (the law's slope over the mass), the faster of the two penetrations' (the larger for n > 1).
// m is the mass the contact carries: the body's against the ground, else the reduced mass
// m_i m_j / (m_i + m_j) of the two bodies (exact for the relative motion of two free bodies; an
// estimate for a body resting on another that rests elsewhere). A contact with neither gravity
// nor an impact velocity holds no scale known before the run, and is left out.
//
// The tolerance that resolves a penetration delta: a coordinate's error is at most tol (1 + |q|)
// (tolerance_choice.hpp), with |q| the largest initial mass-centre coordinate L of the contact's
// bodies; the rule tol (1 + L) <= delta / kPenetrationResolution keeps the force k delta^n within
// about n / kPenetrationResolution of its value (dF / F = n d(delta) / delta).
#pragma once

#include <mbd/model.hpp>

#include <string>
#include <vector>

namespace mbd {

// The position error allowed in a penetration is at most the penetration over this factor.
inline constexpr double kPenetrationResolution = 10.0;

struct ContactScale {
    std::string element;        // the force element's name
    double mass = 0.0;          // the mass the contact carries (kg)
    double penetration = 0.0;   // the smallest penetration it holds (m)
    std::string penetration_source;  // "at rest under its weight 19.6 N" or "at its impact at 2.4 m/s"
    double frequency = 0.0;     // the fastest oscillation, rad/s
    double extent = 0.0;        // L: the largest initial mass-centre coordinate of its bodies (m)
    double tolerance = 0.0;     // penetration / (kPenetrationResolution (1 + L))
};

// The scales of the scene's compliant contacts, in scene order.
std::vector<ContactScale> contact_scales(const Model& model);

}  // namespace mbd
