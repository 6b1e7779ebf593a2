// Static equilibrium by plain Newton on the engine's own equations (generalized forces, their
// Jacobian, the constraints): an independent solver to check `mbd statics` and the flexible
// bodies' forces against closed forms, with the constraints' curvature left out (a slower but
// still convergent iteration).
#pragma once

#include <mbd/model_system.hpp>

#include <Eigen/Dense>
#include <Eigen/Sparse>

namespace mbd::test {

// Equilibrium Q(q) = J^T lambda, C(q) = 0 by Newton on the engine's forces, stiffness and
// constraints (the constraint curvature left out: a slower but still convergent iteration).
inline State newton_equilibrium(ModelSystem& system, State state, double& residual) {
    const int n = system.nv();
    ConstraintValues cv;
    Eigen::VectorXd Q, lambda = Eigen::VectorXd::Zero(system.constraint_rows(true));
    for (int iteration = 0; iteration < 60; ++iteration) {
        system.generalized_forces(state, Q);
        system.constraints(state, cv, true);
        const int m = static_cast<int>(cv.C.size());
        Eigen::SparseMatrix<double> dQ_dq, dQ_dv;
        system.force_jacobians(state, dQ_dq, dQ_dv);
        const Eigen::MatrixXd J = Eigen::MatrixXd(cv.J);
        Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n + m, n + m);
        A.topLeftCorner(n, n) = -Eigen::MatrixXd(dQ_dq);
        A.topRightCorner(n, m) = J.transpose();  // d(Q - J^T lambda) = dQ/dq dq - J^T dlambda, the rows negated
        A.bottomLeftCorner(m, n) = J;
        Eigen::VectorXd r(n + m);
        r.head(n) = Q - J.transpose() * lambda;
        r.tail(m) = -cv.C;
        residual = r.norm();
        if (residual < 1e-12) break;
        const Eigen::VectorXd step = A.fullPivLu().solve(r);
        system.advance_positions(state.q, step.head(n));
        lambda += step.tail(m);
    }
    return state;
}

}  // namespace mbd::test
