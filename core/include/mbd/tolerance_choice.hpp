// The integration tolerance a scene needs: the scales its force elements hold that an
// adaptive integrator must resolve, the automatic tolerance that resolves them, and the
// warnings for a given tolerance that cannot (docs/user-guide.md "The automatic choice").
//
// A regularized friction law (coulomb_law.hpp) sticks only while the sliding speed stays
// below its stiction velocity v_s; an integrator whose velocity errors are as large as v_s
// never sees the contact stick (book Ex. 5.6 at tol 1e-6 and v_s = 1e-9 m/s ends 100 % off).
// dopri5, dop853 and cvode accept a step when each component's error is below
// tol |y| + tol (the one tolerance is relative and absolute), which at a sliding speed of v_s
// is tol (1 + v_s). The rule: tol (1 + v_s) <= v_s / kVelocityResolution, the velocity error
// allowed inside the stiction band a tenth of the band.
//
// The scales are read from the elements' documented keys in the scene as read
// (Model::document, every `base:` and parameter override merged in): a friction element
// (Force::is_friction, or any element with `static_friction` > 0, such as a compliant contact
// with friction) has the velocity scale `stiction_velocity`, m/s or rad/s for a pin's or
// clutch's slip rate, default 1e-6 as its plugins document (friction::CoulombLaw).
#pragma once

#include <mbd/model.hpp>

#include <string>
#include <vector>

namespace mbd {

// The velocity error allowed inside a stiction band is at most its width over this factor.
inline constexpr double kVelocityResolution = 10.0;

// A velocity a force element needs resolved.
struct VelocityScale {
    std::string element;  // the force element's name
    double velocity = 0.0;  // its stiction velocity (m/s, or rad/s for a slip rate)
    double tolerance = 0.0; // the largest tolerance that resolves it, tolerance_resolving(velocity)
};

// v_s / (kVelocityResolution (1 + v_s)): tol (1 + v_s) <= v_s / kVelocityResolution.
double tolerance_resolving(double velocity);

// The velocity scales of the scene's force elements, in scene order.
std::vector<VelocityScale> velocity_scales(const Model& model);

struct ToleranceChoice {
    double tolerance = 0.0;
    std::string reason;  // "the default: no element's scale needs a tighter one", "force 'dry' ..."
};

// The tolerance of a run given none: `fallback` (the default, IntegratorSettings::tolerance),
// or tighter when a scale needs it (the smallest tolerance_resolving of the scales, at least
// kSmallestTolerance).
ToleranceChoice automatic_tolerance(const Model& model, double fallback);

// One warning per element whose scale a given tolerance cannot resolve, naming the element,
// its scale and the tolerance it needs ("" for each resolved one is left out).
std::vector<std::string> tolerance_warnings(const Model& model, double tolerance);

}  // namespace mbd
