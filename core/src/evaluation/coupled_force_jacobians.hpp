// The Jacobians of a force element that implements ForceCouplings (mbd/sdk/force_couplings.hpp),
// one coupling at a time: central differences over each coupling's two bodies, assembled as
// sparse blocks. Memory and cost grow with the couplings (contacts), not with the square of the
// element's velocities, so a collision element over 10,000 bodies has a Jacobian.
#pragma once

#include <mbd/body_poses.hpp>
#include <mbd/model.hpp>
#include <mbd/sdk/force_couplings.hpp>

#include <Eigen/SparseCore>

#include <vector>

namespace mbd {

// The element's ForceCouplings, or null when it has none (then its Jacobians are taken whole).
const ForceCouplings* force_couplings(const ForceInstance& f);

// Adds dQ/dq and dQ/dv of element f at `state` into the triplets (the Model's velocity indices).
// `poses` holds `state`; `view` is a workspace. The differences are those of the whole element
// (ModelSystem::force_differences: the same step, the same perturbed body states), so both agree
// to round-off.
void add_coupled_force_jacobians(const Model& m, const ForceInstance& f, const ForceCouplings& element,
                                 const State& state, const BodyPoses& poses, BodyStates& view,
                                 std::vector<Eigen::Triplet<double>>& dQ_dq,
                                 std::vector<Eigen::Triplet<double>>& dQ_dv);

}  // namespace mbd
