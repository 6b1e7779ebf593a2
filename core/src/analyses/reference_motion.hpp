// The steady motions the linearisation (linearisation.hpp) accepts, and the axes in which it
// measures their perturbations. Internal to the core.
//
// A steady motion here: every body translates at a constant world velocity and turns about a
// body-fixed axis at a constant body-axis rate, v(t) = v0, so that the pose at time t + tau
// is the reference pose advanced by v0 tau (R + Rdot tau, A exp(skew(wbar) tau)); and the
// dynamics are the same all along it. Static equilibria are the case v0 = 0.
#pragma once

#include <mbd/model_system.hpp>

#include <Eigen/Core>

#include <functional>

namespace mbd {

// T = diag(I, A0^T A) per spatial body (identity for planar scenes): the velocity v in the
// reference axes of q0 (a spatial body's angular velocity A0^T A wbar, its translation
// unchanged). Orthogonal, so v = T^T u.
Eigen::MatrixXd reference_axes(const Model& model, const Eigen::VectorXd& q, const Eigen::VectorXd& q0);

// Refuses (LinearisationError) a moving reference that is not a steady motion: a turning
// body's inertia must be symmetric about its axis of rotation (so that turning it along the
// reference is a symmetry of the dynamics: a wheel about its axle), and the
// accelerations `vdot(state)` (all components) must stay within `tolerance` at the reference
// and at the reference advanced by v0 tau, tau a turn of about one radian of its fastest body
// (one second when nothing turns).
void require_steady_motion(const ModelSystem& system, const State& reference,
                           const std::function<Eigen::VectorXd(const State&)>& vdot, double tolerance);

}  // namespace mbd
