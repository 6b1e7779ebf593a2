// Forward dynamics driver (see simulation.hpp).
#include <mbd/simulation.hpp>

#include <mbd/csv.hpp>
#include <mbd/output_sink.hpp>
#include <mbd/formulation_setup.hpp>
#include <mbd/interrupt.hpp>
#include <mbd/method_choice.hpp>
#include <mbd/model_system.hpp>
#include <mbd/output_times.hpp>
#include <mbd/progress_bar.hpp>
#include <mbd/kit/non_finite_motion.hpp>
#include <mbd/reactions.hpp>
#include <mbd/sdk/text.hpp>
#include <mbd/tolerance_choice.hpp>

#include "simulation/energy_growth.hpp"
#include "simulation/friction_dissipation.hpp"
#include "simulation/lift_off.hpp"
#include "simulation/run_setup.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <memory>
#include <sstream>

namespace mbd {

namespace {

double max_abs(const Eigen::VectorXd& x) { return x.size() ? x.lpNorm<Eigen::Infinity>() : 0.0; }

}  // namespace

// Scenes may hold massless bodies (kinematics and statics need no masses), but forward
// dynamics solves M vdot = ..., so a zero mass or principal moment is refused by name.
void require_positive_masses(const Model& model) {
    for (const Body& b : model.bodies) {
        const bool planar = model.dimension == Dimension::Planar;
        const double smallest = planar ? b.inertia(2, 2) : Eigen::SelfAdjointEigenSolver<Mat3>(b.inertia).eigenvalues()[0];
        if (b.mass > 0.0 && smallest > 0.0) continue;
        throw DynamicsError(0.0, "body '" + b.name + "' has " +
                                     (b.mass > 0.0 ? std::string("a zero principal moment of inertia")
                                                   : std::string("zero mass")) +
                                     ": the mass matrix is singular, so its accelerations are undetermined; give it "
                                     "a mass and inertia (a small value is enough for a link meant to be massless), "
                                     "or use `mbd kinematics` / `mbd statics`, which need no masses");
    }
}

std::vector<std::string> reaction_columns(const Model& model) {
    std::vector<std::string> columns;
    const bool planar = model.dimension == Dimension::Planar;
    for (const JointInstance& j : model.joints) {
        if (planar) {
            for (const char* s : {".fx", ".fy", ".tz"}) columns.push_back(j.name + s);
        } else {
            for (const char* s : {".fx", ".fy", ".fz", ".tx", ".ty", ".tz"}) columns.push_back(j.name + s);
        }
    }
    return columns;
}

std::vector<std::string> diagnostic_columns() {
    return {"kinetic_energy", "potential_energy", "constraint_position_violation", "constraint_velocity_violation"};
}

namespace {

// The run's formulation and integrator: the settings' (the command line's), else for the
// formulation the scene's, else the automatic choice (method_choice.hpp), which the run's
// messages report with its reason.
struct RunMethod {
    std::string formulation, integrator;
};
RunMethod run_method(const Model& model, const SimulationSettings& settings) {
    RunMethod method{!settings.formulation.empty() ? settings.formulation : model.formulation, settings.integrator};
    if (!method.formulation.empty() && !method.integrator.empty()) return method;
    const MethodChoice automatic = automatic_method(model, settings.t_end);
    if (method.formulation.empty()) {
        // an integrator that needs the index-3 form (generalized_alpha) takes augmented, the one that has it
        const bool index3 = !method.integrator.empty() && describe_integrator(method.integrator).needs_index3;
        method.formulation = index3 ? "augmented" : automatic.formulation;
        settings.messages("formulation " + method.formulation + " (automatic: " +
                          (index3 ? method.integrator + " needs its index-3 form" : automatic.formulation_reason) + ")");
    }
    if (method.integrator.empty()) {
        method.integrator = automatic.integrator;
        settings.messages("integrator " + automatic.integrator + " (automatic: " + automatic.integrator_reason + ")");
    }
    return method;
}

// The run's formulation `name`, with the scene's keys when it is the scene's formulation, and
// the command line's choices over them.
std::shared_ptr<Formulation> make_run_formulation(const Model& model, Registry& registry,
                                                  const SimulationSettings& settings, const std::string& name,
                                                  FormulationOptions& options) {
    const bool scene_keys = model.formulation_node && model.formulation == name;
    const std::string where =
        (!settings.formulation.empty() || model.formulation_where.empty()) ? std::string() : model.formulation_where;
    std::shared_ptr<Formulation> formulation =
        create_formulation(registry, name, scene_keys ? model.formulation_node.get() : nullptr, where);
    options = scene_keys ? model.formulation_options : FormulationOptions();
    if (settings.stabilization) options.stabilization = *settings.stabilization;
    if (settings.algebra) options.algebra = *settings.algebra;
    if (settings.sparse_threshold) options.sparse_threshold = *settings.sparse_threshold;
    options.log = settings.messages;
    return formulation;
}

void check_integration_settings(const SimulationSettings& settings) {
    if (!(settings.t_end > 0.0) || !std::isfinite(settings.t_end))
        throw InputError("", "the end time must be positive, got " + format_time(settings.t_end));
    const double tolerance = settings.integration.tolerance, step = settings.integration.step;
    if (!(std::isfinite(tolerance) && tolerance > 0.0))
        throw InputError("", "the integration tolerance must be a positive finite number, got " + format_number(tolerance, 9));
    if (!(std::isfinite(step) && step >= 0.0))
        throw InputError("", "the integration step must be a finite number >= 0 (0: none), got " + format_number(step, 9));
}

// The run's integrator settings: for an adaptive integrator the tolerance given, warned of
// when it cannot resolve a scale of the scene, or the automatic one (tolerance_choice.hpp),
// said with its reason as the automatic formulation and integrator are.
IntegratorSettings run_integration(const Model& model, const SimulationSettings& settings, const std::string& integrator) {
    IntegratorSettings integration = settings.integration;
    if (!describe_integrator(integrator).adaptive) return integration;
    if (settings.automatic_tolerance) {
        const ToleranceChoice choice = automatic_tolerance(model, integration.tolerance);
        integration.tolerance = choice.tolerance;
        settings.messages("tolerance " + format_number(choice.tolerance, 3) + " (automatic: " + choice.reason + ")");
    } else {
        for (const std::string& warning : tolerance_warnings(model, integration.tolerance))
            settings.messages("warning: " + warning);
    }
    return integration;
}

// Output times h, 2h, ..., t_end (the start, 0, is written before integrating).
std::vector<double> output_times_after_start(const SimulationSettings& settings) {
    double h = settings.output_step;
    if (h == 0.0) h = settings.integration.step > 0.0 ? settings.integration.step : settings.t_end / 1000.0;
    const long intervals = std::max(1L, output_intervals(settings.t_end, h));
    std::vector<double> times;
    times.reserve(intervals);
    for (long k = 1; k < intervals; ++k) times.push_back(static_cast<double>(k) * h);
    times.push_back(settings.t_end);
    return times;
}

// The reaction columns of one row: each joint's reaction on its second body, world axes, at
// its joint point (planar fx fy tz; spatial fx fy fz tx ty tz).
void append_reactions(System& system, const State& state, const Eigen::VectorXd& lambda, std::vector<double>& row) {
    const bool planar = system.dimension() == Dimension::Planar;
    for (const JointReaction& r : joint_reactions(system, state, lambda)) {
        Vec3 force, torque;
        second_body_load(r, force, torque);
        if (planar) {
            row.insert(row.end(), {force.x(), force.y(), torque.z()});
        } else {
            row.insert(row.end(), force.data(), force.data() + 3);
            row.insert(row.end(), torque.data(), torque.data() + 3);
        }
    }
}

// The columns of every output row, and which optional ones this run writes.
struct OutputLayout {
    std::vector<std::string> columns;
    bool write_H = false;                // the formulation's H (e.g. hamiltonian)
    bool integrate_dissipation = false;  // friction_dissipated, one more ODE state
};

OutputLayout output_layout(const Model& model, const System& system, const Formulation& formulation,
                           const Integrator& integrator, const SimulationSettings& settings) {
    OutputLayout out;
    out.columns = motion_columns(model);
    if (settings.reactions)
        for (auto& c : reaction_columns(model)) out.columns.push_back(c);
    if (settings.diagnostics)
        for (auto& c : diagnostic_columns()) out.columns.push_back(c);
    out.write_H = settings.diagnostics && formulation.has_hamiltonian();
    if (out.write_H) out.columns.push_back("H");
    // the energy friction dissipated, as one more ODE state (friction_dissipation.hpp), with the
    // diagnostics only; an index-3 integrator works on the System's DAE, which has no room for it
    const bool dissipation = settings.diagnostics && system.has_friction();
    out.integrate_dissipation = dissipation && !integrator.needs_index3();
    if (out.integrate_dissipation) out.columns.push_back(kFrictionDissipatedColumn);
    if (dissipation && !out.integrate_dissipation)
        settings.messages("no column " + std::string(kFrictionDissipatedColumn) + ": the " + integrator.name() +
                          " integrator works on the index-3 equations, which have no state for it");
    return out;
}

}  // namespace

void start_events(ContactEvents& events, const Integrator& integrator, const State& state) {
    if (events.count() == 0) return;
    if (!integrator.locates_events())
        throw InputError(integrator.name(), "this integrator does not locate events, and " + events.first_element() +
                                                " has them (a stop's closing and opening): use --integrator " +
                                                integrator_list([](const IntegratorDescription& d) {
                                                    return d.locates_events;
                                                }));
    Eigen::VectorXd g;
    events.values(state, g);
    std::vector<int> side(g.size());
    for (Eigen::Index k = 0; k < g.size(); ++k) side[k] = g[k] < 0.0 ? -1 : +1;
    events.check_start(state, side);
}

long simulation_rows(const SimulationSettings& settings) {
    return static_cast<long>(output_times_after_start(settings).size()) + 1;
}

PreparedRun prepare_run(const Model& model, Registry& registry, const SimulationSettings& settings) {
    PreparedRun run;
    const RunMethod method = run_method(model, settings);
    run.formulation_name = method.formulation;
    const std::string& name = run.formulation_name;
    run.formulation = make_run_formulation(model, registry, settings, name, run.options);
    check_integration_settings(settings);
    run.integration = run_integration(model, settings, method.integrator);
    run.integrator = make_integrator(method.integrator, run.integration);
    const Integrator& integrator = *run.integrator;
    if (integrator.needs_index3() && !run.formulation->index3_problem())
        throw InputError(integrator.name(), integrator.name() +
                                                " needs the formulation's index-3 problem (M vdot + J^T lambda = Q, "
                                                "C(q, t) = 0), which formulation '" +
                                                name + "' does not provide; use --formulation augmented");
    require_velocity_rows_handled(model, *run.formulation, name, integrator.needs_index3(), integrator.name());
    require_reaction_loads_handled(model, *run.formulation, name, integrator.needs_index3(), integrator.name());
    require_flexible_bodies_handled(model, *run.formulation, name, integrator.needs_index3(), integrator.name());
    return run;
}

Eigen::VectorXd consistent_start(ModelSystem& system, Formulation& formulation, State& state, double t) {
    state.t = t;
    system.assemble(state, true);
    system.consistent_velocities(state, true);
    Eigen::VectorXd y;
    formulation.to_ode(state, y);
    if (!formulation.project(t, y))
        throw DynamicsError(t, "the initial state could not be projected onto the constraints");
    return y;
}

void check_simulation_method(const Model& model, Registry& registry, const SimulationSettings& settings) {
    SimulationSettings quiet = settings;  // a check says nothing of the tolerance it would choose
    quiet.messages = MessageLog::silent();
    refuse_scene_inputs(model);
    prepare_run(model, registry, quiet);
}

namespace {

// Each output sample of a run: its row built from the state (motion, reactions, diagnostics,
// H, the dissipated energy), the run's watches checked (lift-off, energy growth), the row
// refused when not finite, then handed to every sink and to the callback.
class RowEmitter {
public:
    RowEmitter(const Model& model, ModelSystem& system, Formulation& formulation, const Integrator& integrator,
               const SimulationSettings& settings, const OutputLayout& layout, const OutputSinks& sinks,
               const SimulationCallback& callback, SimulationResult& result)
        : model_(model), system_(system), formulation_(formulation), settings_(settings), layout_(layout),
          sinks_(sinks), callback_(callback), result_(result), progress_(settings.progress),
          end_text_(" / " + format_time(settings.t_end) + " s"), lift_off_(system),
          energy_(model.drivers.empty() && system.conservative()),  // a conservative scene: no energy may enter
          energy_advice_(integrator.adaptive() ? "use a tighter tolerance (--tol)"
                                               : "use a smaller step (--step), or an adaptive integrator "
                                                 "(--integrator dopri5, dop853 or cvode)"),
          motion_size_(formulation.ode_size()) {}

    bool operator()(double t, const Eigen::VectorXd& y_run) {
        motion_y_ = y_run.head(motion_size_);
        formulation_.from_ode(t, motion_y_, sample_.state);
        if (!sample_.state.q.allFinite() || !sample_.state.v.allFinite())
            throw NonFiniteMotion(t, "non-finite state: the motion diverged (try a smaller tolerance or step)");
        row_ = motion_values(model_, sample_.state);
        append_constraints_and_reactions(t);
        append_energies(t, y_run);
        for (size_t k = 0; k < row_.size(); ++k)
            if (!std::isfinite(row_[k]))
                throw DynamicsError(t, "non-finite value in output column '" + layout_.columns[k] +
                                           "': the motion diverged (try a smaller tolerance or step)");
        for (OutputSink* sink : sinks_) sink->row(row_);
        sample_.row = &row_;
        ++result_.rows;
        result_.final_state = sample_.state;
        if (progress_.due()) progress_.update(t / settings_.t_end, "t = " + format_time(t) + end_text_);  // text only when shown
        stop_if_interrupted(t);  // the row is complete: a stop signal ends the run here
        return callback_ ? callback_(sample_) : true;
    }

    void finish() { progress_.finish(); }

private:
    void append_constraints_and_reactions(double t) {
        system_.constraints_with_velocity_rows(sample_.state, cv_, true);  // their C is 0
        result_.final_position_violation = max_abs(cv_.C);
        Eigen::VectorXd velocity_residual = cv_.C_t;
        if (cv_.J.rows() > 0) velocity_residual += cv_.J * sample_.state.v;
        result_.final_velocity_violation = max_abs(velocity_residual);
        sample_.lambda = nullptr;
        if (settings_.reactions || lift_off_.active()) formulation_.multipliers(sample_.state, lambda_);
        if (settings_.reactions) {
            sample_.lambda = &lambda_;
            append_reactions(system_, sample_.state, lambda_, row_);
        }
        if (lift_off_.active()) lift_off_.check(t, lambda_, settings_.messages, result_.lift_offs);
    }

    void append_energies(double t, const Eigen::VectorXd& y_run) {
        const bool watch_energy = energy_.active(), energies = settings_.diagnostics || watch_energy;
        const double kinetic = energies ? system_.kinetic_energy(sample_.state) : 0.0;
        const double potential = energies ? system_.potential_energy(sample_.state) : 0.0;
        if (watch_energy) energy_.check(t, kinetic, potential, max_abs(cv_.C_t) != 0.0, energy_advice_);
        if (settings_.diagnostics)
            row_.insert(row_.end(), {kinetic, potential, result_.final_position_violation,
                                     result_.final_velocity_violation});
        if (layout_.write_H) row_.push_back(formulation_.hamiltonian(t, motion_y_));
        if (layout_.integrate_dissipation) row_.push_back(y_run[motion_size_]);
    }

    const Model& model_;
    ModelSystem& system_;
    Formulation& formulation_;
    const SimulationSettings& settings_;
    const OutputLayout& layout_;
    const OutputSinks& sinks_;
    const SimulationCallback& callback_;
    SimulationResult& result_;
    ProgressBar progress_;
    const std::string end_text_;
    LiftOffWatch lift_off_;  // contact rows that can only push (a cam follower)
    EnergyGrowthWatch energy_;
    const std::string energy_advice_;
    const int motion_size_;
    Eigen::VectorXd motion_y_, lambda_;
    ConstraintValues cv_;
    SimulationSample sample_;
    std::vector<double> row_;
};

}  // namespace

SimulationResult simulate(const Model& model, Registry& registry, const SimulationSettings& settings,
                          const SimulationCallback& callback, const OutputSinks& sinks) {
    SimulationResult result;
    refuse_scene_inputs(model);  // before the automatic choices evaluate the forces
    PreparedRun run = prepare_run(model, registry, settings);  // before any work
    Formulation& formulation = *run.formulation;
    const Integrator& integrator = *run.integrator;
    result.formulation = run.formulation_name;
    result.integrator = integrator.name();
    result.tolerance = integrator.adaptive() ? run.integration.tolerance : 0.0;

    // --- bind and assemble a consistent initial state
    require_positive_masses(model);
    ModelSystem system(model);
    formulation.bind(system, run.options);
    State state = settings.initial_state ? *settings.initial_state : system.initial_state();
    Eigen::VectorXd y = consistent_start(system, formulation, state, 0.0);

    // --- the rows' columns, to every sink before the first row
    const OutputLayout layout = output_layout(model, system, formulation, integrator, settings);
    result.columns = layout.columns;
    for (OutputSink* sink : sinks) sink->begin(layout.columns);
    RowEmitter emit(model, system, formulation, integrator, settings, layout, sinks, callback, result);

    ContactEvents events(system);
    ContactProblem problem(formulation, system, events, result.events);
    problem.set_breakpoints(scene_breakpoints(model));  // steps end where a `steps` function jumps
    start_events(events, integrator, state);
    FrictionDissipationProblem dissipation(problem, formulation, system);
    OdeProblem& ode = layout.integrate_dissipation ? static_cast<OdeProblem&>(dissipation) : problem;
    if (layout.integrate_dissipation) {
        const int motion_size = formulation.ode_size();
        y.conservativeResize(motion_size + 1);
        y[motion_size] = 0.0;  // E_f(0)
    }
    const std::clock_t cpu_start = std::clock();
    // A failure or a stop ends no sink: a file keeps its complete rows in OUTPUT.partial
    // and the note saying so is kept for the command's message.
    const auto step = [&emit](double t, const Eigen::VectorXd& y_run) { return emit(t, y_run); };
    if (emit(0.0, y)) run.integrator->integrate(ode, 0.0, y, output_times_after_start(settings), step, result.stats);
    result.cpu_seconds = static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
    emit.finish();
    for (OutputSink* sink : sinks) sink->end();
    return result;
}

}  // namespace mbd
