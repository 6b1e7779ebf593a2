// The ODE vector y = [q; v] of the formulations that integrate the coordinates and
// the velocities directly (augmented, amalgamated).
#pragma once

#include <mbd/kit/formulation.hpp>
#include <mbd/kit/state.hpp>
#include <mbd/kit/system.hpp>

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

// A formulation whose ODE vector is y = [q; v] (augmented, amalgamated): the mapping between
// the state and y, once. bind() calls bind_sizes() first.
class CoordinateVelocityFormulation : public Formulation {
public:
    int ode_size() const final { return nq_ + nv_; }
    void to_ode(const State& state, Eigen::VectorXd& y) final { qv_to_ode(state, nq_, nv_, y); }
    void from_ode(double t, const Eigen::VectorXd& y, State& state) final { qv_from_ode(t, y, nq_, nv_, state); }

protected:
    void bind_sizes(const System& system) {
        nq_ = system.nq();
        nv_ = system.nv();
    }
    int nq_ = 0, nv_ = 0;
};

}  // namespace mbd
