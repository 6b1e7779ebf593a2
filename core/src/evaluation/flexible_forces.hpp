// Force elements attached to flexible bodies (docs/architecture.md "Flexible bodies"): a slot of
// the element on a flexible body holds the ground in its `bodies` and sees the material frame at
// its point as a rigid body (Data::fill_view). The element's generalized force on that frame,
// Q_f (3 planar, 6 spatial), acts on the body's coordinates as G^T Q_f, G the frame's Jacobian
// (sdk body.hpp), by virtual work: dW = Q_f . (G dv) = (G^T Q_f) . dv.
#pragma once

#include <mbd/data.hpp>
#include <mbd/model.hpp>

#include <Eigen/SparseCore>

#include <functional>
#include <vector>

namespace mbd {

// Adds each flexible slot's G^T Q_f into Q (the system's velocities); `local` is the element's
// vector over its slots as the plugin wrote it (the rigid slots are scattered by the caller).
void add_flexible_slot_forces(const Model& m, const std::vector<FlexibleAttachment>& attachments,
                              const std::vector<Data::FlexibleSlot>& slots, const Eigen::Ref<const Eigen::VectorXd>& local,
                              Eigen::VectorXd& Q);

// The power of those forces at the frames' velocities, sum of Q_f . (G v_f).
double flexible_slot_power(const Model& m, const std::vector<FlexibleAttachment>& attachments,
                           const std::vector<Data::FlexibleSlot>& slots, const Eigen::Ref<const Eigen::VectorXd>& local,
                           const Data& data);

// The system velocities an element's force depends on: each rigid slot's block, and every
// coordinate of each flexible body it is attached to (each once).
std::vector<int> element_velocity_columns(const Model& m, const ForceInstance& f);

// dQ/dq and dQ/dv of an element with flexible slots, by central differences of its mapped
// force over element_velocity_columns (positions advanced as the integrators do; h = 1e-7,
// as ModelSystem::force_differences). The mapped force G^T Q_f depends on q through the frame
// and through G itself, so the differences take both. `mapped(state, Q)` writes the element's
// force over the whole system (Q sized nv, zero elsewhere).
using MappedForce = std::function<void(const State&, Eigen::VectorXd&)>;
void add_flexible_force_jacobians(const Model& m, const ForceInstance& f, const State& state,
                                  const MappedForce& mapped, std::vector<Eigen::Triplet<double>>& dQ_dq,
                                  std::vector<Eigen::Triplet<double>>& dQ_dv);

}  // namespace mbd
