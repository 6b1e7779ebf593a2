// The automatic choice of formulation and integrator: what `mbd simulate` (and Python's
// Model.simulate) use when neither the command line nor the scene names one. The rules are
// measured on the work-precision bench (docs/user-guide.md "The automatic choice",
// docs/benchmarks.md):
//   formulation  embedding when the joints form a tree its recursive path can take (the fewest
//                states and an O(n) right-hand side: the pendulum, the chains, the gyroscope);
//                augmented otherwise (closed loops, drivers: the four-bars, the car axis, the
//                Bricard), except in a stiff scene (below) that the closure path takes: cvode's
//                difference Jacobian costs one rhs per state and its LU grows with their cube, so
//                the joint coordinates win (the flyball: 8 states against 52, 1.8 times cheaper
//                at error 1e-6).
//   integrator   cvode when the scene is stiff: the fastest rate of its force elements (a compliant
//                contact's frequency counts too: fastest_contact_frequency), the fastest damping rate of its force elements
//                (the largest eigenvalue of M^-1 times the symmetric part of -dQ/dv, at the
//                initial state, and for friction elements also where they stick: every velocity
//                zero, a load from a joint's reaction at its static value; sticking_damping_rate)
//                times the length of the run exceeds kStiffDampedTimeScales, so that an explicit
//                method would need about that many steps for stability alone (the flyball's
//                spring-dampers: 1e5 1/s over 2 s; a block sticking with v_s = 1e-6 m/s: some
//                1e7 1/s); dop853 otherwise (on every non-stiff bench scene it costs less than
//                dopri5 at errors 1e-6 and 1e-9, and about as much at the default tolerance).
//   tolerance    chosen apart, in tolerance_choice.hpp: a run without one takes 1e-6 or the
//                tighter one the scene's stiction velocities need.
#pragma once

#include <mbd/model.hpp>

#include <string>

namespace mbd {

struct MethodChoice {
    std::string formulation;
    std::string integrator;
    std::string formulation_reason;  // "the joints form a tree ...", "1 closed loop (cut joint 'D')"
    std::string integrator_reason;   // "not stiff (...)", "stiff: ..."
};

// A run of length t_end is stiff for an explicit integrator beyond this many damped time scales.
inline constexpr double kStiffDampedTimeScales = 1e4;

// The fastest damping rate of the scene's force elements at its initial state, 1/s (0: no
// damping): the largest eigenvalue of the generalized problem sym(-dQ/dv) x = lambda M x.
double fastest_damping_rate(const Model& model);

// The fastest damping rate of the scene's friction elements (those with a velocity scale,
// tolerance_choice.hpp) while they stick, 1/s (0: none): the largest eigenvalue of
// sym(-dQ/dv) x = lambda M x over their bodies' velocities at the initial positions with every
// velocity zero, each load from a joint's reaction set to its static value (the multipliers
// under the static load; not estimated beyond 2000 constraint rows). `note` says where it came from.
struct StickingDamping {
    double rate = 0.0;
    std::string note;  // "friction sticking (stiction velocity 1e-06), force 'dry' loaded by joint ..."
};
StickingDamping sticking_damping_rate(const Model& model);

// The fastest oscillation of the scene's compliant contacts about the penetrations they hold
// (contact_scales.hpp), rad/s (0: none): a resting contact is a stiff spring that an explicit
// method must follow with steps below about 1 / frequency however still the contact rests,
// while an implicit one steps over it once its ringing has decayed below the tolerance.
struct ContactFrequency {
    double frequency = 0.0;
    std::string note;  // "compliant contact 'ball' oscillating at ... rad/s ..."
};
ContactFrequency fastest_contact_frequency(const Model& model);

MethodChoice automatic_method(const Model& model, double t_end);

}  // namespace mbd
