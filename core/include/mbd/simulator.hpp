// A simulation a program steps (docs/embedding.md): one Model, its own Data (a
// ModelSystem), formulation and integrator, made as simulate() makes them (the same
// settings and automatic choices, simulation.hpp). step() takes one integrator step and
// advance_to(t) continues to t: the integrator keeps its step size and history between
// calls (Integrator::begin / step), so a run cut into many calls is one run. The state can
// be read and written; a written state is assembled onto the constraints and the integrator
// restarts from it. Inputs (time functions {type: input, name: NAME}) take the values
// set_input gives, held until changed; a user force adds generalized forces computed by
// the program in every right-hand side.
//
// Thread safety as Model / Data: any number of Simulators may share one Model, each used by
// one thread at a time; their inputs and forces are their own.
#pragma once

#include <mbd/contact_events.hpp>
#include <mbd/integrator.hpp>
#include <mbd/model.hpp>
#include <mbd/registry.hpp>
#include <mbd/simulation.hpp>

#include <Eigen/Core>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace mbd {

// A force computed by the program: the generalized forces (size Model::nv(), in the order of
// State::v) at a state. Called inside every right-hand side; an exception it throws, or a
// result of the wrong size or not finite, fails the step (DynamicsError naming the cause).
using UserForce = std::function<Eigen::VectorXd(const State& state)>;

// Told of each located event as the step that ends on it completes.
using EventCallback = std::function<void(const EventRecord& event)>;

class Simulator {
public:
    // settings as for simulate(): formulation, integrator, tolerance or step (with their
    // automatic choices), the overrides of the formulation keys, an initial state and the
    // messages. settings.t_end is the expected end of the run: the automatic choice of
    // method and the largest step of the adaptive integrators follow it; it is no limit.
    // Output, reactions, diagnostics and progress do not apply. Throws as simulate() does.
    Simulator(const Model& model, Registry& registry, const SimulationSettings& settings = {});
    ~Simulator();
    Simulator(const Simulator&) = delete;
    Simulator& operator=(const Simulator&) = delete;

    const Model& model() const;
    const std::string& formulation() const;
    std::string integrator() const;
    double tolerance() const;  // of an adaptive integrator; 0 for a fixed step

    // --- stepping. After a failed step (DynamicsError, a user force's error) the state stays
    // that of the last good step, and step() / advance_to() throw until reset().
    void step();                 // one accepted integrator step (it may end on an event)
    void advance_to(double t);   // continue to time t (>= time())

    // --- the state: coordinates q and velocities v at time() (State::q, State::v order).
    double time() const;
    const State& state() const;
    // Restart from `state` at its time state.t: positions assembled onto the constraints, then
    // velocities made consistent (drivers included), as a run's initial state is. The
    // integrator starts afresh (no history). Sizes must be nq / nv, values finite.
    void reset(const State& state);
    void reset();  // the scene's (or settings.initial_state's) initial state at t = 0
    // reset() at time() with these coordinates and velocities.
    void set_state(const Eigen::VectorXd& q, const Eigen::VectorXd& v);
    // One body's coordinates and velocities (planar x y theta / vx vy omega; spatial R p /
    // v_R omega_bar), read and written (set_body_state: reset() with that body's changed).
    Eigen::VectorXd body_coordinates(const std::string& body) const;
    Eigen::VectorXd body_velocities(const std::string& body) const;
    void set_body_state(const std::string& body, const Eigen::VectorXd& q, const Eigen::VectorXd& v);
    // One joint's coordinate and rate (a joint with one: revolute angle, prismatic
    // displacement; the value a driver of it prescribes). set_joint_state changes the state as
    // little as it can (least squares: the minimum-norm change of the positions, then of the
    // velocities) so that the joint has this coordinate and rate and every constraint holds
    // (drivers included: a driven joint keeps its driver's value), then reset()s from it.
    // InputError for an unknown joint or one with no coordinate; KinematicsError for a value
    // the mechanism cannot reach.
    double joint_coordinate(const std::string& joint) const;
    double joint_rate(const std::string& joint) const;
    void set_joint_state(const std::string& joint, double coordinate, double rate);

    // --- inputs: the names the scene's {type: input} time functions use, and their values
    // (0 until set). set_input holds the value from now on (zero-order hold).
    const std::vector<std::string>& input_names() const;
    void set_input(const std::string& name, double value);
    double input(const std::string& name) const;

    // --- a user force (empty: none), and the events.
    void set_user_force(UserForce force);
    void on_event(EventCallback callback);
    const std::vector<EventRecord>& events() const;  // located since the last reset, in time order
    const IntegratorStats& stats() const;            // since the last reset

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace mbd
