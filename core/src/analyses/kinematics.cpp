// Kinematic analysis (book Secs. 3.7-3.8).
//
// Positions: Newton-Raphson on C(q, t) = 0 with minimum-norm steps (book Eqs.
// 3.111-3.117), the increments applied with advance_positions so that spatial
// Euler parameters stay normalised. Velocities: J v = -C_t (Eq. 3.120).
// Accelerations: J a = gamma (Eq. 3.124). Driven motion: at each output time the
// Newton start is the Taylor predictor q + h v + h^2/2 a (Eq. 3.138).
//
// Under-driven models: when the joints and drivers leave degrees of freedom,
// every solve here still has a definite answer. Newton takes minimum-norm steps,
// so the free coordinates stay as close as the constraints allow to the
// predictor (or to the scene's initial positions at t = 0); velocities are the
// consistent ones nearest to the previous velocities (at t = 0: the scene's);
// accelerations are the minimum-norm solution of J a = gamma. The free motion is
// therefore "carried along" rather than prescribed; `mbd check` says whether a
// model is kinematically driven.
#include <mbd/kinematics.hpp>

#include <mbd/interrupt.hpp>
#include <mbd/output_times.hpp>
#include <mbd/sdk/text.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace mbd {

namespace {

// C(q) = 0 at a fixed time, as seen by the Newton solver: x is q, dx is a
// velocity-like increment.
class PositionEquations final : public NonlinearEquations {
public:
    PositionEquations(const ConstraintSystem& system, Data& data, const State& state)
        : system_(system), data_(data), state_(state) {
        if (state_.v.size() != system.cols()) state_.v = Eigen::VectorXd::Zero(system.cols());
    }
    int equations() const override { return system_.rows(); }
    int unknowns() const override { return system_.cols(); }
    void evaluate(const Eigen::VectorXd& x, Eigen::VectorXd& C, Eigen::SparseMatrix<double>& J) override {
        state_.q = x;
        system_.evaluate(state_, data_, values_);
        C = values_.C;
        J = values_.J;
    }
    void advance(Eigen::VectorXd& x, const Eigen::VectorXd& dx) const override {
        advance_positions(system_.model(), x, dx);
    }

private:
    const ConstraintSystem& system_;
    Data& data_;
    State state_;
    ConstraintValues values_;
};

int worst_row(const Eigen::VectorXd& r, double& value) {
    int row = -1;
    value = 0.0;
    for (int k = 0; k < r.size(); ++k)
        if (!(std::abs(r[k]) <= value)) {  // also catches NaN
            value = std::abs(r[k]);
            row = k;
        }
    return row;
}

// After a linear solve J x = b: a residual far above round-off means J is
// singular in a direction b needs (a lock-up or dead-centre configuration, or
// contradictory drivers).
void check_linear_residual(const ConstraintSystem& system, const Eigen::VectorXd& residual, const Eigen::VectorXd& rhs,
                           double t, const char* what) {
    double worst = 0.0;
    const int row = worst_row(residual, worst);
    const double scale = std::max(1.0, rhs.size() ? rhs.cwiseAbs().maxCoeff() : 0.0);
    if (row >= 0 && !(worst <= 1e-6 * scale)) {
        throw KinematicsError(std::string("the ") + what + " equations have no solution at t = " + format_time(t) +
                              ": " + system.owner(row).describe() + " is violated by " + format_number(worst, 3) +
                              ". The constraint Jacobian is singular there (a dead-centre or lock-up position, "
                              "or drivers that contradict the joints); check the driver's motion and which joint "
                              "coordinate it drives");
    }
}

// The solution of J x = b nearest to x0, x0 + J^+ (b - J x0) (minimum-norm correction), for the
// `what` analysis at time t (`quantities` names x in the error): refused when J cannot be
// factored, when a residual stays (check_linear_residual) or when x is not finite.
Eigen::VectorXd nearest_solution(const ConstraintSystem& system, const Eigen::SparseMatrix<double>& J,
                                 const Eigen::VectorXd& b, Eigen::VectorXd x0, double t, LinearAlgebra algebra,
                                 const char* what, const char* quantities) {
    const std::string failed = std::string(what) + " analysis failed at t = " + format_time(t);
    MinNormSolver solver(algebra);
    if (!solver.factor(J)) throw KinematicsError(failed + ": the constraint Jacobian could not be factored");
    x0 += solver.solve(b - J * x0);
    check_linear_residual(system, J * x0 - b, b, t, what);
    if (!x0.allFinite()) throw KinematicsError(failed + ": non-finite " + quantities);
    return x0;
}

}  // namespace

AssemblyReport assemble_positions(const ConstraintSystem& system, Data& data, State& state, const KinematicsOptions& options) {
    AssemblyReport report;
    if (system.rows() == 0) return report;
    PositionEquations equations(system, data, state);
    const NewtonResult result = newton_raphson(equations, state.q, options.newton);
    report.iterations = result.iterations;
    report.residual = result.residual;
    if (!result.converged) {
        std::ostringstream message;
        message << "assembly failed at t = " << format_time(state.t) << " after " << result.iterations
                << " Newton iteration" << (result.iterations == 1 ? "" : "s") << ": ";
        if (result.worst_row >= 0)
            message << system.owner(result.worst_row).describe() << " is violated by "
                    << format_number(result.residual, 3) << " (tolerance " << format_number(options.newton.tolerance, 3)
                    << ")";
        else
            message << "the residual is " << format_number(result.residual, 3);
        message << ". Check the initial positions near this joint, or the driver's motion (a mechanism that cannot "
                   "reach the prescribed position, or passes a dead centre, has no solution)";
        throw KinematicsError(message.str());
    }
    return report;
}

void solve_velocities(const ConstraintSystem& system, Data& data, State& state, LinearAlgebra algebra) {
    if (state.v.size() != system.cols()) state.v = Eigen::VectorXd::Zero(system.cols());
    if (system.rows() == 0) return;
    ConstraintValues values;
    system.evaluate(state, data, values);
    // book Eq. 3.120: J v = -C_t; the given v corrected by the minimum-norm change
    state.v = nearest_solution(system, values.J, -values.C_t, state.v, state.t, algebra, "velocity", "velocities");
}

Eigen::VectorXd solve_accelerations(const ConstraintSystem& system, Data& data, const State& state,
                                    LinearAlgebra algebra) {
    if (system.rows() == 0) return Eigen::VectorXd::Zero(system.cols());
    ConstraintValues values;
    system.evaluate(state, data, values);
    // book Eq. 3.124: J a = gamma, the minimum-norm solution
    return nearest_solution(system, values.J, values.gamma, Eigen::VectorXd::Zero(system.cols()), state.t, algebra,
                            "acceleration", "accelerations");
}

void run_kinematics(const Model& model, double t_end, double step, const KinematicsSample& sample,
                    const KinematicsOptions& options) {
    // Output times t_k = k h, k = 0..n, the last one exactly t_end (output_times.hpp).
    const long long n = output_intervals(t_end, step, "kinematics: the output step", "kinematics: the end time");
    // positions from C(q, t) = 0 alone: a no-slip row leaves them to the motion's history
    require_holonomic(model, "the kinematic analysis", "simulate the motion (`mbd simulate`) instead");

    const ConstraintSystem system(model, true);
    Data data(model);
    const LinearAlgebra algebra = options.newton.algebra;

    State state = model.initial_state();
    state.t = 0.0;
    assemble_positions(system, data, state, options);
    solve_velocities(system, data, state, algebra);
    Eigen::VectorXd a = solve_accelerations(system, data, state, algebra);
    if (!sample(state, a)) return;

    double t_previous = 0.0;
    for (long long k = 1; k <= n; ++k) {
        const double t = (k == n) ? t_end : static_cast<double>(k) * step;
        const double h = t - t_previous;
        // book Eq. 3.138: Taylor predictor for the Newton start
        const Eigen::VectorXd increment = h * state.v + (0.5 * h * h) * a;
        advance_positions(model, state.q, increment);
        state.t = t;
        assemble_positions(system, data, state, options);
        solve_velocities(system, data, state, algebra);
        a = solve_accelerations(system, data, state, algebra);
        if (!sample(state, a)) return;
        t_previous = t;
        stop_if_interrupted(t);  // after a complete sample: SIGINT/SIGTERM/SIGHUP stop here
    }
}

}  // namespace mbd
