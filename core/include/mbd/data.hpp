// Data: everything one evaluation of a Model writes, allocated once when it is created
// (Pinocchio's Model/Data split, MuJoCo's mjModel/mjData). A Model is immutable and may
// be shared by any number of threads; each thread evaluates with its own Data. Nothing
// here is resized on the evaluation path.
#pragma once

#include <mbd/body_poses.hpp>
#include <mbd/model.hpp>

#include <Eigen/Core>

#include <vector>

namespace mbd {

struct Data {
    explicit Data(const Model& model);

    // Bring `poses` to this state's positions and velocities; computed once per state, so
    // the forces and the constraints of one evaluation share them.
    void pose(const State& state);

    BodyPoses poses;          // every body's pose and velocity at the state being evaluated
    BodyStates view;          // the bodies of the element being evaluated
    // one force element's output, sized for the element with the most bodies
    Eigen::VectorXd force_Q, force_plus, force_minus;
    Eigen::MatrixXd force_dQ_dq, force_dQ_dv;
    State probe;              // a perturbed state (finite-difference force Jacobians)
    // each joint's rows and each driver's row, as the element writes them
    std::vector<ConstraintEval> joint_rows;
    std::vector<CoordinateEval> driver_rows;
    // one joint's (d gamma / d v)^T mu over its bodies (Joint::gamma_velocity_transpose)
    Eigen::VectorXd joint_gamma_gradient;
    // each joint's velocity-level rows (sized 0 for a joint without any)
    std::vector<VelocityConstraintEval> joint_velocity_rows;

private:
    Eigen::VectorXd posed_q_, posed_v_;  // the state `poses` holds
    bool posed_ = false;
};

}  // namespace mbd
