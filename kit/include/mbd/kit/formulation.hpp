// The formulation interface: how a plugin writes the equations of motion of a
// System for the integrators (plugin kind "formulation").
//
// Every formulation presents a first-order ODE y' = f(t, y) on a state vector
// of its own choosing (augmented: y = [q; v]; embedding: independent
// coordinates; Hamiltonian: coordinates and momenta), maps it to and from the
// engine's State, and may pull y back onto the constraint manifold after each
// accepted step (coordinate projection). Formulations that can be integrated
// as an index-3 DAE by an implicit integrator provide that DAE as a named problem
// (index3_problem(), kit index3_problem.hpp), through which such an integrator works.
#pragma once

#include <mbd/kit/formulation_options.hpp>
#include <mbd/sdk/params.hpp>
#include <mbd/kit/plugin.hpp>
#include <mbd/kit/system.hpp>

#include <Eigen/Core>

#include <memory>
#include <stdexcept>
#include <string>

namespace mbd {

class Index3Problem;  // kit index3_problem.hpp

// A run that cannot go on (singular saddle point, Newton failure in a
// projection, ...). `time` is when it happened; the message names the cause
// and the joints involved.
class MBD_SDK_API DynamicsError : public std::runtime_error {
public:
    DynamicsError(double time, const std::string& message) : std::runtime_error(message), time_(time) {}
    double time() const { return time_; }

private:
    double time_;
};

class MBD_SDK_API Formulation {
public:
    virtual ~Formulation() = default;

    // Bind to a system; allocate all scratch here so the hot path does not allocate.
    virtual void bind(System& system, const FormulationOptions& options) = 0;

    // --- the ODE y' = f(t, y)
    virtual int ode_size() const = 0;
    // y from a consistent state (assembled, consistent velocities).
    virtual void to_ode(const State& state, Eigen::VectorXd& y) = 0;
    // The engine's state (q, v) from y.
    virtual void from_ode(double t, const Eigen::VectorXd& y, State& state) = 0;
    // f(t, y); throws DynamicsError when the equations cannot be solved.
    virtual void rhs(double t, const Eigen::VectorXd& y, Eigen::VectorXd& ydot) = 0;
    // After an accepted step: pull y back onto the manifold (positions and
    // velocities, unit Euler parameters). Returns false if that failed.
    virtual bool project(double /*t*/, Eigen::VectorXd& /*y*/) { return true; }
    // True once after project() changed the meaning of part of y (a re-selection of
    // the independent coordinates); the call clears it. A multistep integrator must
    // then discard its history and restart from the current (t, y).
    virtual bool state_redefined() { return false; }
    // Whether project() can ever redefine y (a formulation whose y is written in coordinates it
    // re-selects). An integrator that projects inside its steps, where a re-selection has to
    // wait until the step is accepted (CVODE), projects once more after an accepted step only
    // for a formulation that can; for the others that second projection would change nothing.
    // The default is the safe answer.
    virtual bool may_redefine_state() const { return true; }

    // --- results
    // Lagrange multipliers of every constraint row (joints, then drivers, then, for a
    // formulation that handles them, the joints' velocity-level rows) at a consistent
    // state: reactions and actuator efforts come from these.
    virtual void multipliers(const State& state, Eigen::VectorXd& lambda) = 0;
    // Accelerations vdot at a state.
    virtual void accelerations(const State& state, Eigen::VectorXd& vdot) = 0;
    // The formulation's conserved quantity where it has one (Hamiltonian: H).
    virtual bool has_hamiltonian() const { return false; }
    virtual double hamiltonian(double /*t*/, const Eigen::VectorXd& /*y*/) { return 0.0; }

    // True if the formulation obeys the joints' velocity-level (nonholonomic) rows A v = b
    // (joint.hpp; System::constraints_with_velocity_rows). The host refuses a scene with such
    // rows for a formulation that does not, naming the joint.
    virtual bool supports_velocity_constraints() const { return false; }

    // True if the formulation solves the loads of force elements loaded by a joint's reaction
    // (Force::load_joint, friction in pins and guides) together with its multipliers
    // (reaction_loads.hpp). The host refuses such a scene for a formulation that does not,
    // naming the force element.
    virtual bool supports_reaction_loads() const { return false; }

    // The formulation's index-3 problem (kit index3_problem.hpp: M vdot + J^T lambda = Q,
    // C(q, t) = 0 with its residuals, iteration matrix and projection), which an implicit
    // integrator of the index-3 DAE (generalized_alpha) solves; null when the formulation has
    // none (the default), and the host then refuses that integrator naming the formulation.
    // Asked before bind() only for whether there is one; usable after bind().
    virtual Index3Problem* index3_problem() { return nullptr; }
    // True if the formulation takes flexible bodies (System::flexible_coordinates(), sdk
    // body.hpp): a general constant mass matrix block after the rigid bodies' blocks. The core
    // refuses a scene with flexible bodies, naming the body, for a formulation that does not.
    virtual bool supports_flexible_bodies() const { return false; }

    // The groups of shared options (formulation_options.hpp) this formulation honours; the
    // host refuses a scene key of any other group, naming the formulation.
    virtual OptionGroups options_used() const { return 0; }
};

struct FormulationSpec {
    std::string name;   // the formulation's name as selected (same as type)
    std::string type;   // e.g. "augmented"
    // The scene's `formulation:` map, if any. The shared keys are already read into
    // FormulationOptions (and marked read); the factory reads the keys of its own and
    // leaves the rest: the host refuses a key nobody read.
    Params params;
};

using FormulationFactory = std::unique_ptr<Formulation>(const FormulationSpec& spec);

}  // namespace mbd

#define MBD_FORMULATION_PLUGIN(type, factory) MBD_REGISTER_KIT_PLUGIN(formulation, type, factory)

// The calls every formulation implements, declared once for the class bodies that implement
// them (a change of the interface is one edit here): bind, rhs, project, multipliers and
// accelerations; a formulation whose ODE state is not y = [q; v] adds the conversions.
#define MBD_FORMULATION_CALLS                                                      \
    void bind(System& system, const FormulationOptions& options) override;        \
    void rhs(double t, const Eigen::VectorXd& y, Eigen::VectorXd& ydot) override; \
    bool project(double t, Eigen::VectorXd& y) override;                          \
    void multipliers(const State& state, Eigen::VectorXd& lambda) override;       \
    void accelerations(const State& state, Eigen::VectorXd& vdot) override
#define MBD_FORMULATION_STATE_CONVERSIONS                        \
    void to_ode(const State& state, Eigen::VectorXd& y) override; \
    void from_ode(double t, const Eigen::VectorXd& y, State& state) override
