// The state a run owns: time, coordinates q and velocities v (see body_state.hpp
// for their layout per body), and the stacked constraint values of a system.
#pragma once

#include <Eigen/Core>
#include <Eigen/Sparse>

namespace mbd {

struct State {
    double t = 0.0;
    Eigen::VectorXd q;
    Eigen::VectorXd v;
};

// C(q, t), its Jacobian with respect to v, C_t and gamma for every row of a
// system (joints first, then drivers): J v = -C_t, J vdot = gamma.
struct ConstraintValues {
    Eigen::VectorXd C;
    Eigen::SparseMatrix<double> J;
    Eigen::VectorXd C_t;
    Eigen::VectorXd gamma;
};

}  // namespace mbd
