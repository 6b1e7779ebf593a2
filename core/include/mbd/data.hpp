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

    // Flexible bodies (model.hpp FlexibleBodyInstance): each one's coordinates and velocities
    // at the posed state, and for each joint its slots on them (in the order of its `flexible`
    // list): the material frame and the joint's rows mapped to the body's own coordinates
    // (sdk map_frame_rows).
    struct FlexibleSlot {
        MaterialFrame frame;
        Eigen::MatrixXd J;  // J_f G, rows x n
    };
    std::vector<Eigen::VectorXd> flexible_q, flexible_v;
    std::vector<std::vector<FlexibleSlot>> joint_flexible;
    std::vector<std::vector<FlexibleSlot>> driver_flexible;  // per driver, its joint's slots (J: 1 x n)
    std::vector<std::vector<FlexibleSlot>> force_flexible;  // per force element (J unused)
    // Fill `view` for an element's bodies, its flexible slots' material frames at the posed
    // state computed into `slots` and put in place of the ground the slots hold.
    void fill_view(BodyList bodies, const std::vector<FlexibleAttachment>& attachments,
                   std::vector<FlexibleSlot>& slots, double t);

private:
    void pose_flexible(const State& state);
    const Model* model_;
    Eigen::VectorXd posed_q_, posed_v_;  // the state `poses` holds
    bool posed_ = false;
};

}  // namespace mbd
