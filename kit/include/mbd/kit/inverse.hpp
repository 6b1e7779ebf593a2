// The inverse-dynamics interface (plugin kind "inverse"), book Secs. 1.7, 4.7, 6.13.
//
// The drivers prescribe the motion (kinematically driven system); actuators act
// along 1-DOF joint coordinates with generalized force J_s^T tau. At each time
// the efforts tau and the joint multipliers lambda satisfy
//     M vdot + J_joints^T lambda = Q + sum_a J_s(a)^T tau_a,
// with vdot from the drivers. Fully actuated: tau is unique (it equals minus
// the driver multipliers of the augmented formulation, -lambda_d). Redundant:
// minimum sum w_a tau_a^2 subject to the equations and the bounds.
#pragma once

#include <mbd/sdk/params.hpp>
#include <mbd/kit/plugin.hpp>
#include <mbd/kit/system.hpp>

#include <Eigen/Core>

#include <memory>
#include <string>
#include <vector>

namespace mbd {

struct ActuatorInfo {
    std::string name;
    int joint = -1;            // index into System::joint(); acts along its coordinate
    double lo = -1e300;        // effort bounds
    double hi = 1e300;
    double weight = 1.0;
};

struct InverseOptions {
    std::vector<ActuatorInfo> actuators;
    double tolerance = 1e-9;   // relative residual of the equations of motion accepted
    int print_level = 0;       // Ipopt print level for the bounded QPs
};

// One time step of inverse dynamics.
struct InverseSample {
    State state;               // assembled, consistent velocities
    Eigen::VectorXd acceleration;
    Eigen::VectorXd efforts;   // one per actuator
    Eigen::VectorXd lambda;    // joint rows only (the drivers are replaced by the actuators)
    bool bounds_active = false;
    std::string method;        // "exact" | "pseudo-inverse" | "qp"
};

class MBD_SDK_API InverseSolver {
public:
    virtual ~InverseSolver() = default;
    virtual void bind(System& system, const InverseOptions& options) = 0;
    // Efforts at `state` (assembled, consistent velocities, at state.t) with the
    // prescribed acceleration. Throws DynamicsError (formulation.hpp) naming the
    // time and the cause when the motion cannot be produced.
    virtual InverseSample solve(const State& state, const Eigen::VectorXd& acceleration) = 0;
};

struct InverseSpec {
    std::string name;
    std::string type;   // e.g. "ipopt"
    Params params;
};

using InverseFactory = std::unique_ptr<InverseSolver>(const InverseSpec& spec);

}  // namespace mbd

#define MBD_INVERSE_PLUGIN(type, factory) MBD_REGISTER_KIT_PLUGIN(inverse, type, factory)
