// The ODE vector y = [q; v] of the formulations that integrate the coordinates and
// the velocities directly (augmented, amalgamated).
#pragma once

#include <mbd/sdk/state.hpp>

#include <Eigen/Core>

namespace mbd {

// y = [q; v], with nq coordinates and nv velocities
inline void qv_to_ode(const State& state, int nq, int nv, Eigen::VectorXd& y) {
    y.resize(nq + nv);
    y.head(nq) = state.q;
    y.tail(nv) = state.v;
}

// state = (t, q, v) from y = [q; v]
inline void qv_from_ode(double t, const Eigen::VectorXd& y, int nq, int nv, State& state) {
    state.t = t;
    state.q = y.head(nq);
    state.v = y.tail(nv);
}

}  // namespace mbd
