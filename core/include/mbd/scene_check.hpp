// What `mbd check` reports about a scene, and Python's Model.check(): the assembly at t = 0
// with the drivers, the mobility (Gruebler count and rank of C_q, redundant rows), whether
// the drivers prescribe the motion, and which path the embedding formulation would take.
#pragma once

#include <mbd/kinematics.hpp>
#include <mbd/mobility.hpp>
#include <mbd/model.hpp>

#include <string>

namespace mbd {

struct SceneCheck {
    State assembled;                  // the scene's configuration assembled at t = 0, drivers included
    AssemblyReport assembly;
    MobilityReport mobility;          // of the joints (drivers excluded)
    int full_rank = 0;                // rank of [J_joints; J_drivers] (no drivers: mobility.rank)
    int free_dof = 0;                 // velocities - full_rank: the freedoms the drivers leave free
    int dependent_driver_rows = 0;    // driver rows that depend on each other and the joints
    bool kinematically_driven = false;  // drivers present and no freedom left free
    struct {
        std::string path;    // the embedding formulation's `path: auto`: recursive, closure or dense
        std::string reason;  // why it takes that path
    } embedding;
};

// Throws KinematicsError when the scene cannot be assembled at t = 0.
SceneCheck check_scene(const Model& model, double rank_tolerance = 1e-9);

}  // namespace mbd
