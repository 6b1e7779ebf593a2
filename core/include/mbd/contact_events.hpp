// Events of a model's force elements (unilateral stops and contacts: Force::event_count,
// sdk/include/mbd/sdk/force.hpp) and what happens at them: the event functions g of every
// element stacked in scene order, and Newton's impact law on the constrained system.
//
// Impact (book Sec. 5.8's impulse-momentum balance, with the joints' constraint impulses):
// at a closing gap with approach rate gdot- = G v- < 0, the velocity jump dv solves
//     M dv + J^T mu = G^T P,   J dv = 0
// (J: every joint and driver row, so the constraints stay satisfied at the velocity level),
// i.e. dv = P w with w the M-metric projection of M^-1 G^T onto the null space of J, and the
// impulse P = -(1 + e) gdot- / (G w) gives gdot+ = -e gdot-. G w is the stop's effective
// inverse mass; zero means the joints or drivers hold the stop's coordinate fixed (an error).
// A rebound slower than the element's rest_velocity ends at rest (e = 0); the element's
// compliant law then holds the contact, or the run stops with an error when it has none.
#pragma once

#include <mbd/integrator.hpp>
#include <mbd/model_system.hpp>

#include <Eigen/Core>
#include <Eigen/SparseCholesky>

#include <string>
#include <vector>

namespace mbd {

// One located event of a run.
struct EventRecord {
    double time = 0.0;
    std::string force;   // the element's name
    std::string event;   // its name for the event ("lower", "upper")
    std::string kind;    // "impact" (a rebound), "rest" (a plastic impact), "close" (a compliant onset), "open"
    double rate_before = 0.0, rate_after = 0.0;  // gdot just before and after the event
};

class ContactEvents {
public:
    explicit ContactEvents(ModelSystem& system);

    int count() const { return static_cast<int>(entries_.size()); }
    // "force 'stop' (lower)", for messages.
    std::string describe(int event) const;
    // The name of the first element with events ("joint_stop 'stop'"), for messages; empty without.
    std::string first_element() const;

    // g of every event at the state's positions.
    void values(const State& state, Eigen::VectorXd& g);
    // At the located event time state.t: `side` is each event's side (+1 open, -1 closed),
    // already flipped for the events in `crossed`. Applies the impacts of the closings
    // (changing state.v), sets the side an impact leaves (+1 after a rebound, -1 at rest),
    // appends what happened to `log`; true when state.v changed. Throws DynamicsError for a
    // stop that cannot move or that comes to rest without a law to hold it.
    bool handle(State& state, const std::vector<int>& crossed, std::vector<int>& side, std::vector<EventRecord>& log);
    // Refuses a start beyond a stop that has no compliant law to push it back (DynamicsError).
    void check_start(const State& state, const std::vector<int>& side);

private:
    struct Entry {
        int force;  // index in Model::forces
        int local;  // the event's index in its element
    };
    // The element's G of event e scattered into the system's velocity rows (G_), and its EventImpact.
    EventImpact gradient(const State& state, int event);
    // w = M-metric projection of M^-1 G_^T onto the null space of the constraint Jacobian.
    void constrained_response(const State& state);

    ModelSystem& system_;
    std::vector<Entry> entries_;
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> mass_;
    ConstraintValues cv_;
    Eigen::VectorXd element_g_, element_G_, G_, w_;
};

// The formulation's ODE with the model's events: y to State through the formulation, and
// after an impact the new velocities back into y (to_ode, then project).
class ContactProblem final : public FormulationProblem {
public:
    ContactProblem(Formulation& formulation, ModelSystem& system, ContactEvents& events, std::vector<EventRecord>& log)
        : FormulationProblem(formulation, system), formulation_(formulation), events_(events), log_(log) {}
    int event_count() const override { return events_.count(); }
    void event_values(double t, const Eigen::VectorXd& y, Eigen::VectorXd& g) override;
    bool handle_events(double t, Eigen::VectorXd& y, const std::vector<int>& crossed, std::vector<int>& side) override;
    std::string describe_event(int event) const override { return events_.describe(event); }

private:
    Formulation& formulation_;
    ContactEvents& events_;
    std::vector<EventRecord>& log_;
    State state_;
};

}  // namespace mbd
