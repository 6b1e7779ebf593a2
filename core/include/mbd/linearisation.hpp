// Linearised equations of motion in independent coordinates (issue 17), about a static
// equilibrium or a steady motion: x' = A x + B u with x = (z, w), z the independent
// position increments and w the independent velocities of a coordinate partition of the
// constraint Jacobian (book Sec. 6.5), u the scene's actuator efforts.
//
// The reduced equations (book Eqs. 6.79-6.99): from (z, w) the dependent positions follow
// by Newton-Raphson holding z (Sec. 6.12), the dependent velocities from J v + C_t = 0
// (Eq. 6.169), and the accelerations from the augmented system
// [M J^T; J 0] [vdot; lambda] = [Q; gamma] (Eq. 6.128); then z' = w, w' = vdot_i.
// A's velocity-derivative blocks are fourth-order central differences of these reduced
// equations; B is exact (the accelerations are linear in the efforts).
#pragma once

#include <mbd/model_system.hpp>
#include <mbd/sdk/inverse.hpp>

#include <Eigen/Core>

#include <stdexcept>
#include <string>
#include <vector>

namespace mbd {

// The reference state is neither an equilibrium nor a steady motion, or cannot be
// linearised: the message names the residual and what to do.
class LinearisationError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct LinearisationOptions {
    double step = 1e-3;                 // relative difference step (times max(1, |x|))
    double residual_tolerance = 1e-8;   // accepted max |vdot_i| at the reference
};

struct LinearModel {
    State reference;                        // assembled, consistent velocities
    std::vector<std::string> coordinates;   // the independent coordinates, "body.angle"
    std::vector<int> columns;               // their velocity columns
    Eigen::MatrixXd A;                      // 2k x 2k, state (z, w)
    Eigen::MatrixXd B;                      // 2k x actuators
    std::vector<std::string> inputs;        // actuator names
    Eigen::MatrixXd velocity_map;           // nv x k: the full v of each independent one (Eq. 6.80)
    std::vector<std::string> joint_coordinates;  // joints that have a coordinate
    Eigen::MatrixXd joint_map;              // joints x k: their coordinate's rate per independent one
    double residual = 0.0;                  // max |vdot_i| at the reference
};

// Linearises about `reference` (its positions assembled and velocities made consistent
// first). Throws LinearisationError when the residual exceeds the tolerance, the
// constraints are singular there, or the motion is outside what is supported (spatial
// bodies rotating in the reference).
LinearModel linearise(ModelSystem& system, const State& reference, const std::vector<ActuatorInfo>& actuators,
                      const LinearisationOptions& options = {});

}  // namespace mbd
