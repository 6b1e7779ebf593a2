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
//   integrator   cvode when the scene is stiff: the fastest damping rate of its force elements
//                (the largest eigenvalue of M^-1 times the symmetric part of -dQ/dv, at the
//                initial state) times the length of the run exceeds kStiffDampedTimeScales, so
//                that an explicit method would need about that many steps for stability alone
//                (the flyball's spring-dampers: 1e5 1/s over 2 s); dop853 otherwise (on every
//                non-stiff bench scene it costs less than dopri5 at errors 1e-6 and 1e-9, and
//                about as much at the default tolerance).
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

MethodChoice automatic_method(const Model& model, double t_end);

}  // namespace mbd
