// The force interface: what every force plugin implements.
//
// A force element adds generalized forces Q (book Eq. 5.49, delta W = Q^T delta q)
// to the velocity rows of the bodies it touches, in the element's body order,
// one block of velocities_per_body entries per body. For spatial bodies the
// rotational entries are moments in body axes (conjugate to dpi_bar).
// Forces that can supply them also give the Jacobians dQ/dq (with respect to
// the velocity-like position increments, as for joints) and dQ/dv, used by
// implicit integrators and by statics.
#pragma once

#include <mbd/sdk/body_state.hpp>
#include <mbd/sdk/params.hpp>

#include <Eigen/Core>

#include <string>
#include <vector>

namespace mbd {

struct ForceSpec {
    std::string name;
    std::string type;
    Dimension dimension = Dimension::Planar;
    std::vector<BodyInfo> bodies;   // the bodies the force acts on (gravity: all bodies)
    std::vector<Marker> markers;    // application frames, one per body when the force has points
    Vec3 gravity = Vec3::Zero();    // the scene's gravity vector (planar: z = 0)
    Params params;                  // keys not consumed by the core
};

class MBD_SDK_API Force {
public:
    virtual ~Force() = default;

    // Add this element's generalized force to Q (size velocities_per_body * bodies).
    virtual void evaluate(const BodyStates& bodies, Eigen::Ref<Eigen::VectorXd> Q) const = 0;

    // Jacobians of Q: dQ/dq (position increments) and dQ/dv, both square, added into.
    virtual bool has_jacobians() const { return false; }
    virtual void jacobians(const BodyStates& /*bodies*/, Eigen::Ref<Eigen::MatrixXd> /*dQ_dq*/,
                           Eigen::Ref<Eigen::MatrixXd> /*dQ_dv*/) const {}

    // Potential energy of the conservative part (gravity, spring stiffness); the
    // non-conservative part (damping, actuation) is not included.
    virtual double potential_energy(const BodyStates& /*bodies*/) const { return 0.0; }
    // True when Q = -dV/dq exactly (no damping, no time-dependent actuation).
    virtual bool is_conservative() const { return false; }
};

}  // namespace mbd
