// The embedding formulation on absolute coordinates with velocity-level coordinate
// partitioning (Shabana, Computational Dynamics, Sec. 6.5 Eqs. 6.79-6.99 and Sec. 6.12):
// the dense path, for any scene (closed loops, drivers, redundant constraints).
//
// Partition: J (joints + drivers, n_c x n_v, with respect to v) is split by the
// rank-revealing elimination of partition.hpp into dependent columns d (J_d = J[rows, d]
// nonsingular, r x r) and independent columns i (k = n_v - r, the degrees of freedom);
// rows that reduce to zero are redundant and dropped (named once in the message log, FormulationOptions::log).
//   velocities   J_d v_d = -(J_i v_i + C_t)             (book Eq. 6.169 / 6.168)
//   B            v = B v_i,  B_i = I, B_d = -J_d^-1 J_i  (Eqs. 6.80-6.85)
//   gamma'       vdot = B vdot_i + gamma', gamma'_d = J_d^-1 gamma, gamma'_i = 0 (Eqs. 6.90-6.94)
//   dynamics     B^T M B vdot_i = B^T (Q - M gamma')    (Eq. 6.95; Mbar SPD, Cholesky, Eq. 6.99)
//
// ODE state (decision): y = [q; v_i], all n_q coordinates and the k independent velocity
// components. Velocity components of spatial bodies (body-axis angular velocity) are not
// derivatives of coordinates, so the independent set cannot be integrated alone; q is
// integrated from qdot(q, v) and, after every accepted step (project()), the dependent
// positions are corrected by Newton-Raphson holding the independent directions fixed:
// J_d dd = -C, q <- q (+) P_d dd (advance_positions keeps unit Euler parameters). The
// dependent velocities are recomputed from v_i in every evaluation (Eq. 6.169), so the
// velocity constraints hold exactly and the positions to the Newton tolerance: no drift.
//
// Velocity-level (nonholonomic) joint rows A v = b (System::constraints_with_velocity_rows:
// C = 0, J = A, C_t = -b) are partitioned with the holonomic rows: the independent velocities
// v_i span the null space of [J; A], fewer than the positions' degrees of freedom, and since
// all of q is integrated from qdot(q, v) no position is lost; the Newton correction of the
// dependent positions drives the holonomic C to zero (the velocity rows' C is always 0).
//
// Re-selection (Sec. 6.12, L9348-9418): after each accepted step the pivot ratio of J_d
// (smallest / largest pivot of its complete-pivoting LU) is checked; below
// `reselect_ratio` the partition is chosen again by complete pivoting on J at the
// current configuration and v_i is rewritten in the new set (a log line names the time
// and the new set). A switch changes the meaning of y's v_i part, so it is done only in
// the projection of an accepted step (t >= the last rhs time); projections of dense
// output copies inside a step never switch. Multistep integrators (cvode) keep a history
// across the switch; use one-step integrators near singular configurations.
#pragma once


#include <mbd/kit/formulation.hpp>
#include <mbd/kit/partition.hpp>
#include <mbd/kit/velocity_transform.hpp>

#include <mbd/kit/coordinate_selector.hpp>

#include <Eigen/Dense>

#include <limits>
#include <string>
#include <vector>

namespace mbd::embedding {

class Partitioned final : public Formulation {
public:
    // `independent`: the velocity components to prefer as independent ("crank.angle"), if any
    explicit Partitioned(std::vector<std::string> independent) : independent_(std::move(independent)) {}

    MBD_FORMULATION_CALLS;
    MBD_FORMULATION_STATE_CONVERSIONS;
    int ode_size() const override;

    // For tests and diagnostics.
    const CoordinatePartition& partition() const { return part_; }
    int reselections() const { return reselections_; }
    bool state_redefined() override {
        const bool r = redefined_;
        redefined_ = false;
        return r;
    }
    std::string independent_names() const;

private:
    // part_ from J at state (the first time, or on re-selection)
    void select(const State& state, bool initial);
    // dense J (n_c x n_v) and C, C_t, gamma at state (gamma with state.v)
    void evaluate(const State& state);
    // full v from q (in state) and the independent components (Eq. 6.169); needs evaluate()
    void velocities(const Eigen::VectorXd& vi, Eigen::VectorXd& v);
    // vdot (and its pieces) at a consistent state, for partition p; needs evaluate()
    void solve_accelerations(double t, const CoordinatePartition& p, const State& state, Eigen::VectorXd& vdot);
    double jd_pivot_ratio(const CoordinatePartition& p);
    void log_partition(double t, const char* what) const;

    std::vector<std::string> independent_;
    FormulationOptions options_;
    bool log_choices_ = true;  // FormulationOptions::log_choices, default true
    System* system_ = nullptr;
    int nq_ = 0, nv_ = 0, nc_ = 0;
    std::vector<std::string> names_;
    const Eigen::SparseMatrix<double>* M_ = nullptr;  // the System's M (block diagonal): M B in O(n_v k)

    // the partition (mutable: chosen from the first state the formulation sees)
    CoordinatePartition part_;
    bool selected_ = false;
    int reselections_ = 0;
    bool redefined_ = false;  // set by a re-selection in project(), cleared by state_redefined()
    double last_rhs_t_ = -std::numeric_limits<double>::infinity();

    // scratch, sized in bind() or by the first evaluation: the evaluations allocate nothing
    ConstraintValues cv_;
    Eigen::MatrixXd J_;
    State state_;
    Eigen::VectorXd Q_;
    VelocityTransformWorkspace transform_;
    Eigen::MatrixXd B_, MB_, Mbar_;                  // B, M B, B^T M B (Eq. 6.95)
    Eigen::VectorXd gamma_prime_, Mg_, Qbar_, vi_, vdot_i_, vdot_;
    Eigen::LLT<Eigen::MatrixXd> llt_;                // of B^T M B (Eq. 6.99)
    CoordinateSelector selector_;                    // dense or sparse by size (coordinate_selector.hpp)
    CoordinatePartition fresh_;
    Eigen::VectorXd v_before_;
};

}  // namespace mbd::embedding
