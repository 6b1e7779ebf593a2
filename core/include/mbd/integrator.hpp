// Time integrators, shared by all formulations (book Secs. 6.11-6.12 and the
// multibody literature). They see a formulation only through OdeProblem: its
// size, y' = f(t, y), the projection hook after accepted steps and whether it
// redefined y, and, for the implicit index-3 integrator, the DAE behind y (the
// formulation's Index3Problem).
#pragma once

#include <mbd/kit/formulation.hpp>
#include <mbd/kit/system.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace mbd {

// What a run is told and what it counts; the problem and the integrator follow.
struct IntegratorSettings {
    double tolerance = 1e-6;    // relative and absolute tolerance of adaptive integrators
    double step = 0.0;          // fixed step (rk4, generalized_alpha); initial step guess for adaptive ones (0: automatic)
    double min_step = 1e-12;    // below this an adaptive integrator stops with "step size collapse"
    double max_step = 0.0;      // largest step of the explicit pairs dopri5, dop853 (0: the run's span)
    long max_steps = 50000000;
    double rho_infinity = 0.8;  // generalized-alpha spectral radius at infinity
};

struct IntegratorStats {
    long steps = 0;
    long rejected_steps = 0;
    long rhs_evaluations = 0;
    long jacobian_evaluations = 0;
    long newton_iterations = 0;
    long events = 0;  // located events (OdeProblem::event_count)
};

class OdeProblem {
public:
    virtual ~OdeProblem() = default;
    virtual int size() const = 0;
    virtual void rhs(double t, const Eigen::VectorXd& y, Eigen::VectorXd& ydot) = 0;  // throws DynamicsError
    virtual bool project(double t, Eigen::VectorXd& y) = 0;
    // True once after project() changed the meaning of part of y (the call clears it): a
    // multistep integrator then discards its history and restarts from the current (t, y).
    virtual bool state_redefined() { return false; }
    // Whether project() can ever redefine y (Formulation::may_redefine_state); false lets an
    // integrator that projects inside its steps skip the projection after an accepted step.
    virtual bool may_redefine_state() const { return true; }
    // How many trailing components of y are quadratures (their rates depend on the rest, the
    // rest not on them: the energy friction dissipated) that an implicit integrator leaves out
    // of its error control (cvode), integrating them on the steps the motion needs.
    virtual int quadrature_count() const { return 0; }
    // The index-3 DAE M vdot + J^T lambda = Q, C(q, t) = 0 behind y as the formulation
    // provides it (kit index3_problem.hpp), for integrators that solve it (generalized_alpha);
    // null when y has none.
    virtual Index3Problem* index3_problem() { return nullptr; }

    // --- events (docs/integrators.md "Events"): functions g(t, y), each >= 0 on its open
    // side; a sign change is an event (a stop closing or opening). An integrator that
    // locates events (Integrator::locates_events) ends a step exactly on each.
    virtual int event_count() const { return 0; }
    virtual void event_values(double /*t*/, const Eigen::VectorXd& /*y*/, Eigen::VectorXd& /*g*/) {}
    // At a located event (t, y): side[i] is event i's side (+1 open, -1 closed), already
    // flipped for the events listed in `crossed`. The problem acts on them (an impact changes
    // the velocities in y), may set the side an event leaves (a rebound leaves its gap open),
    // and returns true when it changed y: the integrator then restarts from (t, y).
    virtual bool handle_events(double /*t*/, Eigen::VectorXd& /*y*/, const std::vector<int>& /*crossed*/,
                               std::vector<int>& /*side*/) {
        return false;
    }
    // "force 'stop' (lower)", for messages.
    virtual std::string describe_event(int event) const { return "event " + std::to_string(event); }

    // --- breakpoints (docs/integrators.md "Breakpoints"): times where the right-hand side
    // jumps (a piecewise-constant time function's steps). step_toward() ends a step on each,
    // and while a step ends on one (set_step_end), the right-hand side at that time is the
    // value from before the jump: the side of the step being integrated.
    virtual double next_breakpoint(double /*t*/) const { return HUGE_VAL; }  // the first after t
    virtual void set_step_end(double /*t*/) {}  // the breakpoint the current step ends on; NaN: none
};

// The OdeProblem of a formulation bound to a System.
// Its breakpoints are those given to set_breakpoints (scene_breakpoints, run_setup.hpp): at
// the end of a step that ends on one, the formulation's right-hand side is evaluated one
// rounding unit before it, where every piecewise-constant function still has the step's value
// and every smooth one differs by a rounding unit.
class FormulationProblem : public OdeProblem {
public:
    // `system`: the System the formulation is bound to (its index-3 problem works on it)
    FormulationProblem(Formulation& formulation, System& /*system*/) : formulation_(formulation) {}
    int size() const override { return formulation_.ode_size(); }
    void rhs(double t, const Eigen::VectorXd& y, Eigen::VectorXd& ydot) override {
        formulation_.rhs(t == step_end_ ? std::nextafter(t, -HUGE_VAL) : t, y, ydot);
    }
    bool project(double t, Eigen::VectorXd& y) override { return formulation_.project(t, y); }
    bool state_redefined() override { return formulation_.state_redefined(); }
    bool may_redefine_state() const override { return formulation_.may_redefine_state(); }
    Index3Problem* index3_problem() override { return formulation_.index3_problem(); }
    // increasing times
    void set_breakpoints(std::vector<double> times) { breakpoints_ = std::move(times); }
    double next_breakpoint(double t) const override {
        const auto after = std::upper_bound(breakpoints_.begin(), breakpoints_.end(), t);
        return after == breakpoints_.end() ? HUGE_VAL : *after;
    }
    void set_step_end(double t) override { step_end_ = t; }

private:
    Formulation& formulation_;
    std::vector<double> breakpoints_;
    double step_end_ = std::nan("");
};

// Called at every output time with y there; returning false stops the run.
using OutputCallback = std::function<bool(double t, const Eigen::VectorXd& y)>;

// The output times a step passes, for an integrator that reports them from the step's
// continuous extension (Integrator::stops_at_outputs false): step() reports those from
// `next` on that lie before the step's end, advancing `next`, before it accepts the step.
struct StepOutputs {
    const std::vector<double>& times;
    size_t next;
    const OutputCallback& output;
    Eigen::VectorXd stopped;  // the state at the output whose callback returned false
};

// What an integrator is, described once (core/src/integrators/table.cpp) and read by the
// command line's help and checks, Python, the messages and the automatic choice.
struct IntegratorDescription {
    enum class Automatic { Never, NotStiff, Stiff };  // when the automatic choice takes it
    const char* name;
    int order;            // order of accuracy; for a variable-order method its highest (cvode's BDF: 5)
    bool adaptive;        // chooses its own steps for a tolerance; otherwise fixed steps of a given size
    bool locates_events;  // locates the problem's events (OdeProblem::event_count) and ends a step on each
    // Integrates the index-3 form (positions, velocities and multipliers together): the
    // formulation's Index3Problem (Formulation::index3_problem), checked before it binds.
    bool needs_index3;
    bool stiff;           // implicit: its steps are not bounded by the problem's fastest damping
    Automatic automatic;
    const char* summary;  // one line for help and docs
};

// Every integrator, in the order they are listed to the user.
const std::vector<IntegratorDescription>& integrator_descriptions();
// The description of `name`; throws InputError listing the known names for an unknown one.
const IntegratorDescription& describe_integrator(const std::string& name);
// The names of the integrators that `which` selects, as a list for messages: "euler, rk4 or
// generalized_alpha" (`last` joins the last two; ", " for a plain list).
std::string integrator_list(bool (*which)(const IntegratorDescription&), const std::string& last = " or ");
// The integrator the automatic choice takes for a stiff or a not stiff scene.
const IntegratorDescription& automatic_integrator(bool stiff);

// An integrator is resumable (docs/integrators.md "Stepping"): begin() starts a run at
// (t0, y0), each step() takes one step and keeps everything the next needs (step size,
// FSAL derivative, CVODE's history, the generalized-alpha accelerations), so a run cut
// into any number of step() calls continues as one run. integrate() is built on them.
class Integrator {
public:
    virtual ~Integrator() = default;
    // Its row of integrator_descriptions(), set by make_integrator.
    const IntegratorDescription& description() const { return *description_; }
    std::string name() const { return description_->name; }
    bool adaptive() const { return description_->adaptive; }
    bool needs_index3() const { return description_->needs_index3; }
    bool locates_events() const { return description_->locates_events; }

    // Starts a run of `problem` from (t0, y0), discarding any earlier one; t_end is the time
    // the run is expected to reach (it sets the largest step of dopri5, dop853 and cvode and
    // the round-off scale of times, not a limit). The problem and the stats must outlive the run.
    // Throws InputError for bad settings or a state of the wrong size.
    virtual void begin(OdeProblem& problem, double t0, const Eigen::VectorXd& y0, double t_end,
                       IntegratorStats& stats) = 0;
    // One accepted step from time() toward t_stop, never past it (+infinity: no limit); it
    // ends early on a located event, which the problem has handled on return. Output times
    // the step passes go to `outputs` (if given); false when an output's callback stopped
    // the run. Throws DynamicsError naming the time and the cause.
    virtual bool step(double t_stop, StepOutputs* outputs = nullptr) = 0;
    // The run's time and its state there (projected onto the constraints).
    virtual double time() const = 0;
    virtual const Eigen::VectorXd& state() const = 0;
    // The right-hand side changed from time() on (an input set, a force changed): a step
    // keeps its size but no derivative computed before (dopri5's and dop853's FSAL stage).
    virtual void rhs_changed() {}
    // Whether the steps must stop on every output time (the fixed-step integrators, cvode);
    // otherwise outputs inside a step come from its continuous extension (dopri5, dop853).
    virtual bool stops_at_outputs() const { return true; }

    // Advance y from t0 through every output time (increasing, the last is the
    // end time): begin(), then step() until the last output. Throws DynamicsError naming
    // the time and the cause.
    void integrate(OdeProblem& problem, double t0, Eigen::VectorXd& y, const std::vector<double>& output_times,
                   const OutputCallback& output, IntegratorStats& stats);

private:
    friend std::unique_ptr<Integrator> make_integrator(const std::string&, const IntegratorSettings&);
    const IntegratorDescription* description_ = nullptr;
};

// integrator.step(t_stop, outputs), ending the step on the problem's next breakpoint when it
// comes first (the right-hand side evaluated from the step's side there); a step that ends on
// one tells the integrator the right-hand side changed (rhs_changed) for the next.
bool step_toward(Integrator& integrator, OdeProblem& problem, double t_stop, StepOutputs* outputs = nullptr);

// The integrator of that name (integrator_descriptions()). Throws InputError listing the known names.
std::unique_ptr<Integrator> make_integrator(const std::string& name, const IntegratorSettings& settings);
std::vector<std::string> integrator_names();

// Tolerances below this are beneath the round-off of double precision.
constexpr double kSmallestTolerance = 1e-14;

// How an interface writes one of its options in a message: the command line "--step 1e-3",
// Python "step=1e-3". `option` is the option's name with dashes ("output-step"); `value`, as
// the user would type it on the command line, may be empty (the option alone).
using OptionSpelling = std::function<std::string(const std::string& option, const std::string& value)>;
std::string command_line_spelling(const std::string& option, const std::string& value);

// The integrator options of a run, refused where they do not apply (InputError naming the
// option as `spell` writes it, docs/integrators.md): a tolerance for a fixed-step integrator
// or outside [kSmallestTolerance, 1], a step for an adaptive one, a fixed-step integrator
// without a step, or a step that needs more than IntegratorSettings::max_steps steps to t_end.
// An unknown integrator is refused as make_integrator does.
void check_integrator_options(const std::string& integrator, bool tolerance_given, double tolerance, bool step_given,
                              double step, double t_end, const OptionSpelling& spell);

}  // namespace mbd
