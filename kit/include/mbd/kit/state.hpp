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

    // t = 0 and zero coordinates and velocities of these sizes: a workspace made ready once
    void set_zero(int nq, int nv) {
        t = 0.0;
        q.setZero(nq);
        v.setZero(nv);
    }
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
