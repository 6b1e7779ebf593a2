// Finite-difference validation of joint and force plugins: a joint's Jacobian
// against central differences of C, its gamma against the second time
// derivative of C along random smooth trajectories (Cddot = J vdot - gamma),
// the same for its driver coordinate, and its velocity-level rows A v = b (the derivative
// of A v - b along the trajectory against A vdot - gamma; A and b independent of v), and its
// Joint::gamma_velocity_transpose against central differences of gamma in v (exact: gamma is quadratic
// in v); a force's Jacobians against central
// differences of Q, and Q = -dV/dq for conservative forces. The states are
// random and off the constraint manifold, and the joint geometry can be made
// random too (with_random_joint_geometry), so that no term of J or gamma is
// multiplied by a zero marker offset or a special axis. Used by the generic
// joint test and by `mbd plugin check`.
#pragma once

#include <mbd/model.hpp>

#include <random>
#include <string>

namespace mbd {

struct DerivativeErrors {
    // relative errors (|a - b| / max(1, |b|)), worst over the trials
    double jacobian = 0.0;
    double gamma = 0.0;
    double time_derivative = 0.0;     // joints: C_t against Cdot - J v
    double coordinate_jacobian = 0.0;
    double coordinate_gamma = 0.0;
    double gamma_velocity_transpose = 0.0;  // joints with the hook: (d gamma / d v)^T w against differences of gamma
    double velocity_gamma = 0.0;      // velocity-level rows: gamma against A vdot - d/dt (A v - b)
    double velocity_dependence = 0.0; // velocity-level rows: change of A and b with v (must be 0)
    double velocity_jacobian = 0.0;   // forces: dQ/dv
    double potential = 0.0;           // conservative forces: Q + dV/dq
    double event_gradient = 0.0;      // forces with events: G of event_impact against differences of g
    double load_affinity = 0.0;       // friction: evaluate_at_load's departure from affine in the load
    bool finite = true;               // every value evaluated was finite
    std::string worst_state;          // a description of the state behind the largest error

    double worst() const;
};

// A copy of a scene's YAML text whose joints have random geometry, drawn from `rng`
// (seeded: reproducible): each joint gets a random `point` (the origin of its markers,
// so the marker offsets from the bodies' mass centres are random and non-zero), a
// random `axis` (planar: the marker angle; spatial: the frame's z axis, with a random
// perpendicular `x_axis` when the joint has one) or a random perpendicular pair `axes`,
// and random points in `points` (one point per body in body axes, as the distance
// joint takes them). Other keys are kept.
std::string with_random_joint_geometry(const std::string& scene_yaml, std::mt19937& rng);

// A random state near the scene's configuration, off any constraint manifold: position
// increments from N(0, spread^2), velocities velocity_factor times draws of the same, at time t.
State random_state(const Model& model, std::mt19937& rng, double spread, double velocity_factor, double t);

DerivativeErrors check_joint_derivatives(const Model& model, const JointInstance& joint, std::mt19937& rng,
                                         int trials = 5);
DerivativeErrors check_force_derivatives(const Model& model, const ForceInstance& force, std::mt19937& rng,
                                         int trials = 5);

}  // namespace mbd
