// The multibody system as analysis plugins see it (formulations, statics,
// inverse dynamics). The core implements it over its Model; plugins include
// only this header, never core headers.
//
// Layout: q and v per body as in body_state.hpp; constraint rows are every
// joint's rows in scene order, then one row per driver, then (only where asked for:
// constraints_with_velocity_rows) every joint's velocity-level (nonholonomic) rows in
// scene order. Every Jacobian is with
// respect to v (spatial: (dR, dpi_bar)); position increments are applied with
// advance_positions().
//
// A System is one immutable Model together with one evaluation workspace (the core's
// Data): the evaluation methods write that workspace, so they are not const, and one
// System serves one thread at a time. Threads share the Model, each with its own System.
// Constraint Jacobians keep one sparsity pattern for the life of the System (entries that
// happen to be zero are stored), so a factorization's symbolic analysis can be reused.
#pragma once

#include <exception>

#include <mbd/sdk/body_state.hpp>
#include <mbd/sdk/force.hpp>
#include <mbd/sdk/joint.hpp>
#include <mbd/kit/state.hpp>
#include <mbd/sdk/time_function.hpp>

#include <Eigen/Core>
#include <Eigen/Sparse>

#include <memory>
#include <string>
#include <vector>

namespace mbd {

struct JointInfo {
    std::string name;
    std::string type;
    std::vector<int> bodies;        // body indices; -1 is the ground
    std::vector<Marker> markers;    // the joint frame on each body
    int first_row = 0;              // its rows in the constraint vector
    int rows = 0;
    std::shared_ptr<const Joint> joint;
    // its velocity-level rows A v = b (joint.hpp), at constraint_rows(include_drivers) +
    // velocity_row_offset in a stack with velocity rows
    int velocity_row_offset = 0;
    int velocity_rows = 0;
};

struct DriverInfo {
    std::string name;
    int joint = -1;                 // the driven joint
    int row = 0;                    // its row in the constraint vector (after all joint rows)
};

struct ForceInfo {
    std::string name;
    std::string type;
    std::vector<int> bodies;
    std::shared_ptr<const Force> force;
    int load_joint = -1;            // the joint whose reaction is its load (Force::load_joint), -1 none
};

class MBD_SDK_API System {
public:
    virtual ~System() = default;

    // --- description
    virtual Dimension dimension() const = 0;
    virtual const std::string& name() const = 0;
    virtual int body_count() const = 0;
    virtual const BodyInfo& body(int index) const = 0;      // mass, inertia, initial pose
    // Flexible bodies' coordinates (sdk body.hpp) follow every rigid body's in q and v (their
    // velocities are their coordinates' rates); formulations that take them
    // (Formulation::supports_flexible_bodies) see their blocks in mass_matrix().
    virtual int flexible_coordinates() const { return 0; }
    // A joint's slot on a flexible body, the material frame seen as a rigid body (sdk body.hpp):
    // its pose at `state` (rotation A and origin R, world axes; planar: embedded) and the joint's
    // own rows' Jacobian over the frame's velocities (J_frame: the joint's rows x
    // velocities_per_body; planar (dR, dtheta), spatial (dR, dpi_bar)), from which
    // mbd/reactions.hpp takes the reaction on that slot. False for a rigid body or the ground.
    virtual bool joint_material_frame(const State& /*state*/, int /*joint*/, int /*slot*/, Mat3& /*A*/,
                                      Vec3& /*R*/, Eigen::MatrixXd& /*J_frame*/) {
        return false;
    }
    // The same for a driver's row (its joint's coordinate; J_frame: 1 x velocities_per_body).
    virtual bool driver_material_frame(const State& /*state*/, int /*driver*/, int /*slot*/, Mat3& /*A*/,
                                       Vec3& /*R*/, Eigen::MatrixXd& /*J_frame*/) {
        return false;
    }
    int nq() const { return body_count() * coordinates_per_body(dimension()) + flexible_coordinates(); }
    int nv() const { return body_count() * velocities_per_body(dimension()) + flexible_coordinates(); }
    virtual Vec3 gravity() const = 0;

    virtual int joint_count() const = 0;
    virtual const JointInfo& joint(int index) const = 0;
    virtual int driver_count() const = 0;
    virtual const DriverInfo& driver(int index) const = 0;
    // a driver's prescribed coordinate f(t) with its first and second derivatives (the row
    // s(q) - f(t) = 0): a formulation that holds the driven joint in its own coordinates
    // prescribes the motion instead of keeping the row (the embedding's recursive path)
    virtual TimeValue driver_motion(int index, double t) const = 0;
    virtual int force_count() const = 0;
    virtual const ForceInfo& force(int index) const = 0;
    int joint_rows() const { return joint_count() ? joint(joint_count() - 1).first_row + joint(joint_count() - 1).rows : 0; }
    int constraint_rows(bool include_drivers = true) const { return joint_rows() + (include_drivers ? driver_count() : 0); }
    // the joints' velocity-level (nonholonomic) rows, which restrict v but not q
    int velocity_constraint_rows() const {
        if (!joint_count()) return 0;
        const JointInfo& last = joint(joint_count() - 1);
        return last.velocity_row_offset + last.velocity_rows;
    }
    // the first joint with velocity-level rows, -1 if none (for refusals by name)
    int first_nonholonomic_joint() const {
        for (int j = 0; j < joint_count(); ++j)
            if (joint(j).velocity_rows > 0) return j;
        return -1;
    }
    // "joint 'O' (x)" or "driver 'motor'", for messages; rows from constraint_rows(true) on
    // are the velocity-level rows, as in constraints_with_velocity_rows(state, out, true)
    virtual std::string describe_row(int row) const = 0;

    // --- state
    virtual State initial_state() const = 0;               // as given in the scene (not assembled)
    virtual void advance_positions(Eigen::VectorXd& q, const Eigen::VectorXd& dv) const = 0;
    virtual Eigen::VectorXd coordinate_rates(const Eigen::VectorXd& q, const Eigen::VectorXd& v) const = 0;
    virtual void normalize(Eigen::VectorXd& q) const = 0;  // unit Euler parameters

    // --- dynamics terms
    // Constant block-diagonal mass matrix: planar diag(m, m, J); spatial diag(m I, Jbar); then
    // each flexible body's constant mass matrix (its block after the rigid ones).
    virtual const Eigen::SparseMatrix<double>& mass_matrix() const = 0;
    // All applied generalized forces plus, for spatial bodies, the gyroscopic
    // term -wbar x (Jbar wbar) (book Eq. 7.155's Q_v). Q has size nv.
    virtual void generalized_forces(const State& state, Eigen::VectorXd& Q) = 0;
    // dQ/dq (position increments) and dQ/dv of generalized_forces(): exact where the
    // force elements give Jacobians, central finite differences for the others.
    virtual void force_jacobians(const State& state, Eigen::SparseMatrix<double>& dQ_dq,
                                 Eigen::SparseMatrix<double>& dQ_dv) = 0;
    virtual double kinetic_energy(const State& state) const = 0;
    virtual double potential_energy(const State& state) = 0;  // conservative parts
    virtual bool conservative() const = 0;                          // every force conservative

    // --- loads from joint reactions (Force::load_joint: friction in pins and guides) and friction
    // The force indices of the elements whose load is a joint's reaction, in scene order.
    virtual const std::vector<int>& reaction_loaded_forces() const = 0;
    // The loads N (one per reaction-loaded element, in that order) that generalized_forces()
    // applies: a formulation solves them together with the multipliers (kit reaction_loads.hpp)
    // and sets them; 0 until set.
    virtual void set_reaction_loads(const Eigen::VectorXd& loads) = 0;
    virtual const Eigen::VectorXd& reaction_loads() const = 0;
    // dQ/dN of each reaction-loaded element at a state: column k of G (nv x count) for element k
    // (Q is affine in N), and the element's load axis (Force::load_axis, world).
    virtual void reaction_load_directions(const State& state, Eigen::MatrixXd& G, std::vector<Vec3>& axes) = 0;
    // Whether a force element is dry friction (Force::is_friction), and the power of those elements,
    // sum Q_f^T v at the current reaction loads (<= 0: the rate friction dissipates energy).
    virtual bool has_friction() const = 0;
    virtual double friction_power(const State& state) = 0;

    // --- constraints (joints, then drivers when include_drivers)
    virtual void constraints(const State& state, ConstraintValues& out, bool include_drivers = true) = 0;
    // gamma of those rows alone (out.gamma of constraints()), for callers that evaluate it at
    // many velocities: nothing else is assembled
    virtual void constraint_gamma(const State& state, Eigen::VectorXd& gamma, bool include_drivers = true) = 0;
    // out += (d gamma / d v)^T mu over the rows of the joints that provide this product
    // (Joint::has_gamma_velocity_transpose); mu has one weight per row of constraints(). Rows of
    // other joints and of drivers add nothing: the caller differentiates those itself.
    virtual void gamma_velocity_transpose(const State& state, const Eigen::VectorXd& mu, Eigen::VectorXd& out) = 0;
    // Every row the velocities obey: the rows of constraints() followed by the joints'
    // velocity-level rows A v = b, written as rows with no position residual: C = 0, J = A,
    // C_t = -b, gamma = the joint's gamma, so that J v + C_t = 0 and J vdot = gamma hold for
    // every row alike (book Eqs. 3.120, 3.124). The same as constraints() when
    // velocity_constraint_rows() == 0.
    virtual void constraints_with_velocity_rows(const State& state, ConstraintValues& out,
                                                bool include_drivers = true) = 0;

    // --- kinematics (the core's Newton-Raphson; throws std::runtime_error naming the worst joint)
    virtual void assemble(State& state, bool include_drivers = true) = 0;  // positions
    // velocities: J v + C_t = 0 for every row, the velocity-level rows included
    virtual void consistent_velocities(State& state, bool include_drivers = true) = 0;
};

// The state at which a formulation picks its coordinate partition in bind(): the scene's
// initial state assembled as the run will assemble it, or as given when the assembly fails
// (the run itself then reports that failure).
inline State assembled_initial_state(System& system) {
    State s = system.initial_state();
    s.t = 0.0;
    try {
        system.assemble(s, true);
    } catch (const std::exception&) {
        s = system.initial_state();
        s.t = 0.0;
    }
    return s;
}

}  // namespace mbd
