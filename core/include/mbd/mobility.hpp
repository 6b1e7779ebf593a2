// Degrees of freedom by the Gruebler count and by the rank of C_q, and the
// names of redundant constraint rows when the two differ; with velocity-level
// rows, also the freedoms of the velocities.
#pragma once

#include <mbd/constraint_system.hpp>

#include <string>
#include <vector>

namespace mbd {

struct MobilityReport {
    int coordinates = 0;          // velocity coordinates (3 or 6 per body)
    int constraint_rows = 0;      // joint rows (drivers excluded)
    int driver_rows = 0;
    int gruebler_dof = 0;         // coordinates - constraint_rows
    int rank = 0;                 // rank of the joint Jacobian
    int rank_dof = 0;             // coordinates - rank
    std::vector<RowOwner> redundant;  // rows dependent on earlier rows
    // nonholonomic joints: their velocity-level rows A v = b, and the freedoms of the
    // velocities, coordinates - rank [C_q; A] (a rolling disc: 5 of position, 3 of velocity)
    int velocity_rows = 0;
    int velocity_dof = 0;
};

MobilityReport analyse_mobility(const Model& model, const State& state, double rank_tolerance = 1e-9);

}  // namespace mbd
