// Kinematic analysis (book Secs. 3.7-3.8): assembly from an approximate
// configuration by Newton-Raphson, consistent velocities and accelerations,
// and kinematically driven motion with the Taylor predictor (Eq. 3.138).
#pragma once

#include <mbd/constraint_system.hpp>
#include <mbd/newton.hpp>

#include <functional>
#include <stdexcept>
#include <string>

namespace mbd {

// Assembly or a kinematic step failed; the message names the worst-violated
// joint or driver and says what to do.
class KinematicsError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct KinematicsOptions {
    NewtonOptions newton;
};

struct AssemblyReport {
    int iterations = 0;
    double residual = 0.0;
};

// Positions: solve C(q, t) = 0 from state.q (min-norm Newton steps). Throws KinematicsError.
// Each writes its evaluations into `data` (a Data of the system's model).
AssemblyReport assemble_positions(const ConstraintSystem& system, Data& data, State& state,
                                  const KinematicsOptions& options = {});
// Velocities: the consistent velocity nearest to state.v (J v = -C_t).
void solve_velocities(const ConstraintSystem& system, Data& data, State& state, LinearAlgebra algebra = LinearAlgebra::Auto);
// Accelerations: the minimum-norm solution of J a = gamma.
Eigen::VectorXd solve_accelerations(const ConstraintSystem& system, Data& data, const State& state,
                                    LinearAlgebra algebra = LinearAlgebra::Auto);

// Positions, velocities and accelerations at every output time t = 0, h, 2h, ..., t_end.
// The callback sees each sample; returning false stops the run.
using KinematicsSample = std::function<bool(const State& state, const Eigen::VectorXd& acceleration)>;
void run_kinematics(const Model& model, double t_end, double step, const KinematicsSample& sample,
                    const KinematicsOptions& options = {});

}  // namespace mbd
