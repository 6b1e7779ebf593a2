// The `beam_slider` joint (docs/scene-format.md "Joints"): a point P of a collar (a rigid body,
// or the ground) that stays on the centre line of a flexible body (a curve, sdk body_curve.hpp)
// and slides along it without friction, as Exudyn's JointSliding2D or Chrono's point-on-beam
// constraints. Its first body is the flexible body, {body: NAME, at: s0} (the collar starts at
// s0), its second the collar; P is the joint's point on the collar.
//
// The sliding parameter is solved inside the joint, as the cam and contact joints solve their
// surface parameters: at each evaluation s* is the closest point of the curve to P, a global
// search over the curve's pieces then Newton on phi(s) = (r_P - r(q, s)) . r_s(q, s) = 0, so the
// evaluation keeps no state (one Model, many Data). The rows are the components of
// d = r_P - r(q, s*) across the tangent, C = N^T d (planar: N the unit normal, 1 row; spatial:
// two unit normals, 2 rows). With N^T r_s = 0 and d = 0 on the constraint manifold:
//     J     = N^T [J_P, -S(s*)]                                      (the terms times d vanish)
//     gamma = -(2 Ndot^T w + sdot^2 N^T r_ss + N^T (a_P - a_S))        (Cddot = J vdot - gamma, Eq. 3.124)
// with w = rdot_P - rdot(q, s*) the relative velocity, sdot = (w . r_s + d . rdot_s) /
// (|r_s|^2 - d . r_ss) the rate of s* (the derivative of phi = 0), Ndot the normals' rate through
// the tangent's rate rdot_s + r_ss sdot, a_P and a_S the accelerations of P and of the curve's
// material point at vdot = 0 (derivation in beam_slider.cpp).
#pragma once

#include <mbd/model.hpp>
#include <mbd/sdk/joint.hpp>

#include <memory>

namespace mbd {

constexpr const char* kBeamSliderType = "beam_slider";

std::unique_ptr<Joint> make_beam_slider(const JointSpec& spec);

// The scene's checks of a beam_slider: its first body a flexible body that is a curve, its
// second a rigid body or the ground; an InputError naming the joint and its file:line otherwise.
void check_beam_slider(const Model& model, const JointInstance& joint);

}  // namespace mbd
