// A simulation a program steps (simulator.hpp).
#include <mbd/simulator.hpp>

#include <mbd/model_system.hpp>
#include <mbd/sdk/text.hpp>

#include "integrators/embedded_runge_kutta.hpp"
#include "evaluation/joint_state.hpp"
#include "simulation/run_setup.hpp"

#include <algorithm>
#include <cmath>
#include <exception>

namespace mbd {

namespace {

std::string joined(const std::vector<std::string>& names) {
    std::string out;
    for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
    return out.empty() ? std::string("none") : out;
}

// The Simulator's input values (time_function.hpp InputValues), one per name of the scene.
class InputTable final : public InputValues {
public:
    explicit InputTable(const Model& model) {
        for (const SceneInput& input : scene_inputs(model))
            if (std::find(names_.begin(), names_.end(), input.name) == names_.end()) names_.push_back(input.name);
        values_.assign(names_.size(), 0.0);
    }
    const std::vector<std::string>& names() const { return names_; }
    double value(const std::string& name) const override { return values_[index(name)]; }
    void set(const std::string& name, double value) { values_[index(name)] = value; }

private:
    size_t index(const std::string& name) const {
        const auto it = std::find(names_.begin(), names_.end(), name);
        if (it == names_.end())
            throw InputError("input '" + name + "'", "the scene has no input of this name; its inputs are: " +
                                                         joined(names_) + " (time functions {type: input, name: ...})");
        return static_cast<size_t>(it - names_.begin());
    }
    std::vector<std::string> names_;
    std::vector<double> values_;
};

// Makes a Simulator's inputs the current ones of this thread while it evaluates.
class CurrentInputs {
public:
    explicit CurrentInputs(const InputValues& inputs) : previous_(current_input_values()) {
        current_input_values() = &inputs;
    }
    ~CurrentInputs() { current_input_values() = previous_; }
    CurrentInputs(const CurrentInputs&) = delete;
    CurrentInputs& operator=(const CurrentInputs&) = delete;

private:
    const InputValues* previous_;
};

}  // namespace

struct Simulator::Impl {
    Impl(const Model& m, Registry& registry, const SimulationSettings& s)
        : model(m), settings(s), inputs(m), run(prepared(m, registry, s, inputs)) {}

    // prepare_run with the inputs current: the automatic choices may evaluate the forces
    static PreparedRun prepared(const Model& m, Registry& registry, const SimulationSettings& s,
                                const InputTable& inputs) {
        CurrentInputs current(inputs);
        return prepare_run(m, registry, s);
    }

    const Model& model;
    SimulationSettings settings;
    InputTable inputs;
    PreparedRun run;
    std::unique_ptr<ModelSystem> system;
    std::unique_ptr<ContactEvents> contact;
    std::vector<EventRecord> records;
    std::unique_ptr<ContactProblem> problem;
    UserForce user_force;
    EventCallback event_callback;
    IntegratorStats stats;
    State state;            // at the last good step
    std::string failure;    // why the last step failed; empty: none
    bool rhs_changed = false;  // an input or the user force changed since the last step
    size_t reported = 0;    // events told to event_callback
    // An integrator with a continuous extension (dopri5, dop853) in a scene without events:
    // advance_to reports times inside its steps from it instead of cutting a step there, and
    // `state` may lag the integrator (lagging: state.t < its time, y_reported the y at state.t).
    integrators::EmbeddedRungeKutta* dense = nullptr;
    bool lagging = false;
    Eigen::VectorXd y_reported;
    std::vector<double> target = {0.0};  // advance_to's time, as the one output time of a step
    const OutputCallback no_output;
    double expected_end = 0.0;  // the run's expected end (begin): interpolating steps end there, as simulate()'s do

    void begin(State start);
    void after_step();
    void add_user_force(const State& s, Eigen::VectorXd& Q) const;
    template <class Step>
    void stepping(Step&& step);
};

void Simulator::Impl::add_user_force(const State& s, Eigen::VectorXd& Q) const {
    if (!user_force) return;
    Eigen::VectorXd f;
    try {
        f = user_force(s);
    } catch (const std::exception& e) {
        throw DynamicsError(s.t, "the user force failed at t = " + format_time(s.t) + ": " + e.what());
    }
    if (f.size() != Q.size())
        throw DynamicsError(s.t, "the user force returned " + std::to_string(f.size()) +
                                     " values at t = " + format_time(s.t) + "; it must return " +
                                     std::to_string(Q.size()) + " generalized forces (one per velocity, in State::v order)");
    if (!f.allFinite())
        throw DynamicsError(s.t, "the user force returned a value that is not finite at t = " + format_time(s.t));
    Q += f;
}

void Simulator::Impl::begin(State start) {
    const int nq = model.nq(), nv = model.nv();
    if (start.q.size() != nq || start.v.size() != nv)
        throw InputError("state", "needs " + std::to_string(nq) + " coordinates and " + std::to_string(nv) +
                                      " velocities, got " + std::to_string(start.q.size()) + " and " +
                                      std::to_string(start.v.size()));
    if (!std::isfinite(start.t) || !start.q.allFinite() || !start.v.allFinite())
        throw InputError("state", "the time, coordinates and velocities must be finite (a NaN or infinity was given)");
    CurrentInputs current(inputs);
    const double t0 = start.t;
    Eigen::VectorXd y = consistent_start(*system, *run.formulation, start, t0);
    start_events(*contact, *run.integrator, start);
    const double t_end = t0 < settings.t_end ? settings.t_end : t0 + settings.t_end;
    expected_end = t_end;
    records.clear();
    reported = 0;
    stats = IntegratorStats();
    try {
        run.integrator->begin(*problem, t0, y, t_end, stats);  // evaluates the right-hand side (a user force)
    } catch (const std::exception& e) {
        failure = e.what();  // the integrator is not started: no stepping until a reset succeeds
        throw;
    }
    run.formulation->from_ode(t0, run.integrator->state(), state);
    state.t = t0;
    failure.clear();
    rhs_changed = false;
    lagging = false;
}

void Simulator::Impl::after_step() {
    lagging = false;
    const double t = run.integrator->time();
    run.formulation->from_ode(t, run.integrator->state(), state);
    state.t = t;
    while (reported < records.size()) {
        const EventRecord& event = records[reported++];
        if (event_callback) event_callback(event);
    }
}

template <class Step>
void Simulator::Impl::stepping(Step&& step) {
    if (!failure.empty())
        throw DynamicsError(state.t, "the simulator failed at an earlier step (" + failure +
                                         "); call reset() before stepping again");
    CurrentInputs current(inputs);
    try {
        if (rhs_changed && lagging) {
            dense->rewind(state.t, y_reported);  // the steps past state.t had the old right-hand side
            lagging = false;
        } else if (rhs_changed) {
            run.integrator->rhs_changed();
        }
        rhs_changed = false;
        step();
    } catch (const std::exception& e) {
        failure = e.what();
        throw;
    }
}

Simulator::Simulator(const Model& model, Registry& registry, const SimulationSettings& settings)
    : impl_(std::make_unique<Impl>(model, registry, settings)) {
    Impl& s = *impl_;
    CurrentInputs current(s.inputs);
    require_positive_masses(model);
    s.system = std::make_unique<ModelSystem>(model);
    s.run.formulation->bind(*s.system, s.run.options);
    s.system->set_extra_force([&s](const State& state, Eigen::VectorXd& Q) { s.add_user_force(state, Q); });
    s.contact = std::make_unique<ContactEvents>(*s.system);
    s.problem = std::make_unique<ContactProblem>(*s.run.formulation, *s.system, *s.contact, s.records);
    s.problem->set_breakpoints(scene_breakpoints(model));
    if (s.contact->count() == 0) s.dense = dynamic_cast<integrators::EmbeddedRungeKutta*>(s.run.integrator.get());
    reset();
}

Simulator::~Simulator() = default;

const Model& Simulator::model() const { return impl_->model; }
const std::string& Simulator::formulation() const { return impl_->run.formulation_name; }
std::string Simulator::integrator() const { return impl_->run.integrator->name(); }
double Simulator::tolerance() const { return impl_->run.integrator->adaptive() ? impl_->run.integration.tolerance : 0.0; }

void Simulator::step() {
    Impl& s = *impl_;
    s.stepping([&] { step_toward(*s.run.integrator, *s.problem, HUGE_VAL); });
    s.after_step();
}

void Simulator::advance_to(double t) {
    Impl& s = *impl_;
    if (!std::isfinite(t) || t < s.state.t)
        throw InputError("advance_to", "the time must be finite and not before the current time " +
                                           format_time(s.state.t) + " (got " + format_time(t) +
                                           "); to go back, reset() to a state");
    // Right after a change of the right-hand side (an input set: a control loop) the steps end
    // on t, where the next change will come; otherwise they go their own length and t is
    // read from the continuous extension (docs/embedding.md, "advance_to").
    const bool interpolating = s.dense && !s.rhs_changed;
    s.stepping([&] {
        Integrator& integrator = *s.run.integrator;
        s.target[0] = t;
        while (integrator.time() < t) {
            StepOutputs outputs{s.target, 0, s.no_output, {}};  // computes the extension of the step that passes t
            step_toward(integrator, *s.problem, interpolating ? std::max(t, s.expected_end) : t,
                        interpolating ? &outputs : nullptr);
            s.after_step();
        }
        if (s.lagging && integrator.time() == t) s.after_step();  // caught up with the integrator
        if (integrator.time() == t || !s.dense->interpolate(t, s.y_reported)) return;
        s.run.formulation->from_ode(t, s.y_reported, s.state);
        s.state.t = t;
        s.lagging = true;
    });
}

double Simulator::time() const { return impl_->state.t; }
const State& Simulator::state() const { return impl_->state; }

void Simulator::reset(const State& state) { impl_->begin(state); }

void Simulator::reset() {
    Impl& s = *impl_;
    State start = s.settings.initial_state ? *s.settings.initial_state : s.system->initial_state();
    start.t = 0.0;
    s.begin(start);
}

void Simulator::set_state(const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
    State next;
    next.t = time();
    next.q = q;
    next.v = v;
    reset(next);
}

namespace {

int named_body(const Model& model, const std::string& body) {
    const int index = model.body_index(body);
    if (index >= 0) return index;
    std::vector<std::string> names;
    for (const Body& b : model.bodies) names.push_back(b.name);
    throw InputError("body '" + body + "'", "the scene has no moving body of this name; its bodies are: " + joined(names));
}

}  // namespace

Eigen::VectorXd Simulator::body_coordinates(const std::string& body) const {
    const Model& m = impl_->model;
    return impl_->state.q.segment(m.q_offset(named_body(m, body)), coordinates_per_body(m.dimension));
}

Eigen::VectorXd Simulator::body_velocities(const std::string& body) const {
    const Model& m = impl_->model;
    return impl_->state.v.segment(m.v_offset(named_body(m, body)), velocities_per_body(m.dimension));
}

void Simulator::set_body_state(const std::string& body, const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
    const Model& m = impl_->model;
    const int index = named_body(m, body);
    const int nqb = coordinates_per_body(m.dimension), nvb = velocities_per_body(m.dimension);
    if (q.size() != nqb || v.size() != nvb)
        throw InputError("body '" + body + "'", "needs " + std::to_string(nqb) + " coordinates and " +
                                                    std::to_string(nvb) + " velocities, got " +
                                                    std::to_string(q.size()) + " and " + std::to_string(v.size()));
    State next = impl_->state;
    next.q.segment(m.q_offset(index), nqb) = q;
    next.v.segment(m.v_offset(index), nvb) = v;
    reset(next);
}

double Simulator::joint_coordinate(const std::string& joint) const {
    return mbd::joint_coordinate(*impl_->system, impl_->state, joint).value;
}

double Simulator::joint_rate(const std::string& joint) const {
    return mbd::joint_coordinate(*impl_->system, impl_->state, joint).rate;
}

void Simulator::set_joint_state(const std::string& joint, double coordinate, double rate) {
    if (!std::isfinite(coordinate) || !std::isfinite(rate))
        throw InputError("joint '" + joint + "'", "the coordinate and rate must be finite");
    State next = impl_->state;
    set_joint_coordinate(*impl_->system, next, joint, coordinate, rate);
    reset(next);
}

const std::vector<std::string>& Simulator::input_names() const { return impl_->inputs.names(); }

void Simulator::set_input(const std::string& name, double value) {
    if (!std::isfinite(value))
        throw InputError("input '" + name + "'", "the value must be finite, got " + format_number(value, 9));
    if (impl_->inputs.value(name) != value) impl_->rhs_changed = true;
    impl_->inputs.set(name, value);
}

double Simulator::input(const std::string& name) const { return impl_->inputs.value(name); }

void Simulator::set_user_force(UserForce force) {
    impl_->user_force = std::move(force);
    impl_->rhs_changed = true;
}
void Simulator::on_event(EventCallback callback) { impl_->event_callback = std::move(callback); }
const std::vector<EventRecord>& Simulator::events() const { return impl_->records; }
const IntegratorStats& Simulator::stats() const { return impl_->stats; }

}  // namespace mbd
