// One case of a study (study_case.hpp): the engine's own analyses (simulation.hpp,
// statics_analysis.hpp, linearisation.hpp and modes.hpp), called as `mbd simulate`, `mbd
// statics`, `mbd inverse` and `mbd modes` call them, on the Model with the case's values.
#include <mbd/app/study_case.hpp>

#include <mbd/app/failure_kind.hpp>
#include <mbd/app/study_metrics.hpp>
#include <mbd/app/sweep_runner.hpp>
#include <mbd/csv.hpp>
#include <mbd/interrupt.hpp>
#include <mbd/kinematics.hpp>
#include <mbd/linearisation.hpp>
#include <mbd/model_system.hpp>
#include <mbd/modes.hpp>
#include <mbd/scene_parameters.hpp>
#include <mbd/simulation.hpp>
#include <mbd/statics_analysis.hpp>

#include <algorithm>

namespace mbd {

namespace {

bool uses_any(const Study& study, const std::vector<std::string>& columns) {
    auto used = [&](const std::string& c) {
        return std::find(columns.begin(), columns.end(), c) != columns.end();
    };
    for (const StudyMetric& m : study.metrics)
        if (used(m.column)) return true;
    for (const std::string& s : study.series)
        if (used(s)) return true;
    return false;
}

std::vector<std::string> statics_columns(const Model& model) {
    std::vector<std::string> columns = motion_columns(model);
    for (const JointInstance& j : model.joints)
        if (j.joint->has_coordinate()) columns.push_back(j.name + ".coordinate");
    for (const std::string& c : reaction_columns(model)) columns.push_back(c);
    for (const Driver& d : model.drivers) columns.push_back(d.name + ".effort");
    columns.push_back("residual");
    columns.push_back("iterations");
    return columns;
}

std::vector<std::string> modes_columns(const Model& model) {
    std::vector<std::string> columns;
    for (int k = 1; k <= model.nv(); ++k)
        for (const char* what : {".natural_frequency", ".damped_frequency", ".damping_ratio"})
            columns.push_back("mode" + std::to_string(k) + what);
    return columns;
}

// Collects what a case keeps of its result rows: the metrics and the series.
class CaseTable {
public:
    CaseTable(const Study& study, const std::vector<std::string>& columns) : metrics_(study.metrics, columns) {
        for (const std::string& s : study.series)
            series_columns_.push_back(static_cast<std::size_t>(
                std::find(columns.begin(), columns.end(), s) - columns.begin()));
    }
    void add(const std::vector<double>& row) {
        metrics_.add(row);
        for (std::size_t c : series_columns_) series_.push_back(row[c]);
    }
    void into(CaseResult& r) {
        r.metrics = metrics_.values();
        r.series_rows = series_columns_.empty() ? 0 : metrics_.rows();
        r.series = std::move(series_);
    }

private:
    MetricAccumulator metrics_;
    std::vector<std::size_t> series_columns_;
    std::vector<double> series_;
};

void run_simulate(const Study& study, const Model& model, Registry& registry, CaseResult& out) {
    SimulationSettings s = study.analysis.run;
    s.reactions = uses_any(study, reaction_columns(model));
    s.diagnostics = uses_any(study, diagnostic_columns());
    s.progress = false;
    s.messages = MessageLog::silent();
    std::vector<std::string> columns = motion_columns(model);
    if (s.reactions)
        for (const std::string& c : reaction_columns(model)) columns.push_back(c);
    if (s.diagnostics)
        for (const std::string& c : diagnostic_columns()) columns.push_back(c);
    CaseTable table(study, columns);
    simulate(model, registry, s, [&](const SimulationSample& sample) {
        table.add(*sample.row);
        return true;
    });
    table.into(out);
}

StaticsOptions statics_options(const StudyAnalysis& a, const Model& model) {
    StaticsOptions o;
    o.time = a.time;
    o.objective = a.objective;
    o.tolerance = a.statics_tolerance;
    o.max_iterations = a.max_iterations;
    o.limits = scene_joint_limits(model);
    return o;
}

// The statics of the case; false (with the failure set) when they did not converge.
bool solve_statics(const Study& study, const Model& model, Registry& registry, StaticsReport& report, CaseResult& out) {
    report = run_statics(model, registry, statics_options(study.analysis, model), study.analysis.solver);
    if (report.result.converged) return true;
    out.failure = "statics";
    out.message = "no equilibrium: " + report.result.message;
    return false;
}

void run_statics_case(const Study& study, const Model& model, Registry& registry, CaseResult& out) {
    StaticsReport report;
    if (!solve_statics(study, model, registry, report, out)) return;
    State state = report.result.state;
    state.t = study.analysis.time;
    if (state.v.size() != model.nv()) state.v = Eigen::VectorXd::Zero(model.nv());
    std::vector<double> row = motion_values(model, state);
    for (std::size_t j = 0; j < model.joints.size(); ++j)
        if (model.joints[j].joint->has_coordinate()) row.push_back(report.coordinates[j]);
    for (const JointLoad& l : report.reactions) {
        if (model.dimension == Dimension::Planar) {
            row.insert(row.end(), {l.force.x(), l.force.y(), l.torque.z()});
        } else {
            row.insert(row.end(), {l.force.x(), l.force.y(), l.force.z(), l.torque.x(), l.torque.y(), l.torque.z()});
        }
    }
    const int joint_rows = static_cast<int>(report.result.lambda.size()) - static_cast<int>(model.drivers.size());
    for (std::size_t d = 0; d < model.drivers.size(); ++d) row.push_back(-report.result.lambda[joint_rows + d]);
    row.push_back(report.result.residual);
    row.push_back(report.result.iterations);
    CaseTable table(study, statics_columns(model));
    table.add(row);
    table.into(out);
}

void run_inverse_case(const Study& study, const Model& model, Registry& registry, CaseResult& out) {
    CaseTable table(study, inverse_columns(model, true));
    run_inverse(model, registry, study.analysis.run.t_end, study.analysis.run.integration.step,
                [&](const InverseSample& sample, System& system) {
                    table.add(inverse_row(sample, system, true));
                    stop_if_interrupted(sample.state.t);
                    return true;
                }, InverseOptions{}, study.analysis.solver);
    table.into(out);
}

void run_modes_case(const Study& study, const Model& model, Registry& registry, CaseResult& out) {
    State reference = model.initial_state();
    if (study.analysis.about == "statics") {
        StaticsReport report;
        if (!solve_statics(study, model, registry, report, out)) return;
        reference = report.result.state;
        reference.v = Eigen::VectorXd::Zero(model.nv());
    }
    ModelSystem system(model);
    const ModeAnalysis analysis = modes_of(linearise(system, reference, scene_actuators(model)));
    const std::vector<std::string> columns = modes_columns(model);
    std::vector<double> row(columns.size(), 0.0);
    for (std::size_t k = 0; k < analysis.modes.size() && 3 * k + 2 < row.size(); ++k) {
        row[3 * k] = analysis.modes[k].natural_frequency;
        row[3 * k + 1] = analysis.modes[k].damped_frequency;
        row[3 * k + 2] = analysis.modes[k].damping_ratio;
    }
    // a metric on a mode the case does not have is a failure of the case, not a zero
    for (const StudyMetric& m : study.metrics) {
        const std::size_t column = static_cast<std::size_t>(std::find(columns.begin(), columns.end(), m.column) - columns.begin());
        if (column / 3 >= analysis.modes.size()) {
            out.failure = "modes";
            out.message = "metric " + m.name + ": the case has " + std::to_string(analysis.modes.size()) + " modes";
            return;
        }
    }
    CaseTable table(study, columns);
    table.add(row);
    table.into(out);
}

}  // namespace

std::vector<std::string> case_columns(const Model& model, const StudyAnalysis& analysis) {
    switch (analysis.type) {
    case AnalysisType::Simulate: {
        std::vector<std::string> columns = motion_columns(model);
        for (const std::string& c : reaction_columns(model)) columns.push_back(c);
        for (const std::string& c : diagnostic_columns()) columns.push_back(c);
        return columns;
    }
    case AnalysisType::Inverse: return inverse_columns(model, true);
    case AnalysisType::Statics: return statics_columns(model);
    case AnalysisType::Modes: return modes_columns(model);
    }
    return {};
}

CaseResult run_case(const Study& study, Registry& registry, const std::vector<double>& values) {
    CaseResult out;
    const double cpu_start = thread_cpu_seconds();
    bool assembling = false;
    try {
        SceneParameterValues changes;
        for (std::size_t k = 0; k < study.parameters.size(); ++k) changes.emplace_back(study.parameters[k].path, values[k]);
        Model model;
        try {
            model = with_scene_parameters(*study.model, changes, registry);
        } catch (const InputError& e) {
            out.failure = "scene";
            out.message = e.what();
            out.cpu_seconds = thread_cpu_seconds() - cpu_start;
            return out;
        }
        assembling = true;
        switch (study.analysis.type) {
        case AnalysisType::Simulate: run_simulate(study, model, registry, out); break;
        case AnalysisType::Statics: run_statics_case(study, model, registry, out); break;
        case AnalysisType::Inverse: run_inverse_case(study, model, registry, out); break;
        case AnalysisType::Modes: run_modes_case(study, model, registry, out); break;
        }
        out.ok = out.failure.empty();
    } catch (const KinematicsError& e) {
        out.failure = failure_kind(e.what(), assembling);
        out.message = e.what();
    } catch (const DynamicsError& e) {
        out.failure = failure_kind(e.what(), false);
        out.message = e.what();
    } catch (const LinearisationError& e) {
        out.failure = "linearisation";
        out.message = e.what();
    } catch (const InputError& e) {
        out.failure = "input";
        out.message = e.what();
    } catch (const std::exception& e) {
        out.failure = "error";
        out.message = e.what();
    }
    if (!out.ok) {
        out.metrics.clear();
        out.series.clear();
        out.series_rows = 0;
    }
    out.cpu_seconds = thread_cpu_seconds() - cpu_start;
    return out;
}

}  // namespace mbd
