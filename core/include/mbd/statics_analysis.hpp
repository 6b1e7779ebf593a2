// Statics and inverse dynamics over a Model (issue 6): builds the ModelSystem,
// fills the plugin inputs (joint limits, actuators) from the scene, creates the
// solver plugin through the registry, and computes joint reactions with
// <mbd/reactions.hpp>. Used by `mbd statics`, `mbd inverse` and the tests.
#pragma once

#include <mbd/constraint_system.hpp>
#include <mbd/model.hpp>
#include <mbd/model_system.hpp>
#include <mbd/registry.hpp>
#include <mbd/kit/inverse.hpp>
#include <mbd/kit/statics.hpp>

#include <Eigen/Core>

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace mbd {

// The reaction a joint exerts on its second body (or, when that is the ground,
// the opposite of the reaction on the first), at the joint point, world axes.
struct JointLoad {
    std::string name;
    Vec3 force = Vec3::Zero();
    Vec3 torque = Vec3::Zero();
};

// Reactions an equilibrium does not determine. With redundant constraint rows (as `mbd check`
// names them) J^T has a null space: the equilibrium fixes the constraint forces J^T lambda but
// not lambda, which a solver returns with any self-stress its tolerance leaves in it (a straight
// toggle: 4e5 N from nothing). The report then holds the minimum-norm multipliers, the only
// ones with no self-stress, and names the joints (and drivers) whose rows a self-stress loads.
struct StaticIndeterminacy {
    std::vector<RowOwner> redundant_rows;          // analyse_mobility's, at the equilibrium
    std::vector<std::string> undetermined_joints;  // joints whose rows carry a null vector of J^T
    std::vector<std::string> undetermined_drivers;
    bool any() const { return !redundant_rows.empty(); }
};

struct StaticsReport {
    StaticsResult result;                    // result.lambda: minimum-norm when indeterminacy.any()
    StaticIndeterminacy indeterminacy;
    std::vector<JointLoad> reactions;        // every joint, scene order
    std::vector<JointLoad> driver_efforts;   // every driver (the effort holding its joint)
    std::vector<double> coordinates;         // every joint's coordinate (NaN when it has none)
};

std::vector<JointLimit> scene_joint_limits(const Model& model);
std::vector<ActuatorInfo> scene_actuators(const Model& model);

// Equilibrium from the scene's configuration assembled at options.time.
// Throws KinematicsError when the start cannot be assembled, InputError for an
// unknown solver type or an option out of its range (naming it: "objective",
// "hessian", "tolerance", "max_iterations", "time"); a solver failure is reported
// in result.converged/message.
StaticsReport run_statics(const Model& model, Registry& registry, StaticsOptions options,
                          const std::string& solver = "ipopt");

// The indeterminacy of the multipliers `lambda` (every joint and driver row) at an equilibrium
// `state`; when there is one, `lambda` is replaced by the minimum-norm multipliers with the same
// J^T lambda.
StaticIndeterminacy resolve_indeterminacy(const Model& model, System& system, const State& state,
                                          Eigen::VectorXd& lambda);

// Reactions from multipliers of every constraint row (or of the joint rows only).
std::vector<JointLoad> joint_loads(System& system, const State& state, const Eigen::VectorXd& lambda);

// What inverse dynamics needs of the scene before any work (holonomic constraints, actuators:
// the options' or the scene's); InputError naming the scene otherwise.
void check_inverse_dynamics(const Model& model, const InverseOptions& options = {});

// Inverse dynamics at t = 0, step, ..., t_end (kinematics from the drivers).
// Throws DynamicsError naming the first time it fails, KinematicsError when the
// drivers cannot be assembled.
using InverseCallback = std::function<bool(const InverseSample& sample, System& system)>;
void run_inverse(const Model& model, Registry& registry, double t_end, double step, const InverseCallback& callback,
                 InverseOptions options = {}, const std::string& solver = "ipopt");

// The columns of an inverse-dynamics result (`mbd inverse --output`): t, one per actuator,
// then with `reactions` each joint's reaction (reaction_columns of simulation.hpp).
std::vector<std::string> inverse_columns(const Model& model, bool reactions);
// One sample in those columns.
std::vector<double> inverse_row(const InverseSample& sample, System& system, bool reactions);

}  // namespace mbd
