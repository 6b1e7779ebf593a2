// A joint's coordinate and rate (a revolute's angle, a prismatic's displacement: the joints
// with a coordinate, Joint::has_coordinate), read from a state and written onto one
// (Simulator::joint_coordinate / set_joint_state, docs/embedding.md).
#pragma once

#include <mbd/model_system.hpp>

#include <string>

namespace mbd {

struct JointCoordinate {
    double value = 0.0;  // s(q)
    double rate = 0.0;   // sdot = J_s v
};

// The joint named `joint` at `state`. InputError for a name the model does not have (the
// names listed) or a joint without a coordinate.
JointCoordinate joint_coordinate(ModelSystem& system, const State& state, const std::string& joint);

// `state` changed as little as it can be (least-squares: the minimum-norm increment of the
// positions, then of the velocities) so that the joint's coordinate is `value` and its rate
// `rate` while every constraint (drivers included) still holds: Newton on [C; s - value] = 0
// with the matrix [J; J_s], then [J; J_s] v = [-C_t; rate]. KinematicsError when the
// positions do not converge (a value the mechanism cannot reach).
void set_joint_coordinate(ModelSystem& system, State& state, const std::string& joint, double value, double rate);

}  // namespace mbd
