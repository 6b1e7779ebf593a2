// The analyses of a model from Python: forward dynamics, statics and inverse dynamics, each
// with the GIL released while the engine works, and result tables written as `mbd` writes them.
#include "bindings.hpp"

#include <mbd/app/statics_json.hpp>
#include <mbd/csv.hpp>
#include <mbd/formulation_setup.hpp>
#include <mbd/integrator.hpp>
#include <mbd/linear_algebra.hpp>
#include <mbd/output_file.hpp>
#include <mbd/output_times.hpp>
#include <mbd/sdk/text.hpp>
#include <mbd/simulation.hpp>
#include <mbd/statics_analysis.hpp>

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <chrono>
#include <cmath>
#include <ctime>
#include <optional>

namespace mbd::python {

namespace {

// Options as Python writes them in messages: output_step=0.01, integrator='dopri5'.
std::string python_spelling(const std::string& option, const std::string& value) {
    std::string name = option;
    for (char& c : name)
        if (c == '-') c = '_';
    if (value.empty()) return name;
    double number = 0.0;
    const bool numeric = parse_number(value, number) == NumberText::Valid;
    return name + "=" + (numeric ? value : "'" + value + "'");
}

void require_one_of(const std::string& option, const std::string& value, const std::vector<std::string>& allowed) {
    for (const std::string& a : allowed)
        if (value == a) return;
    std::string listed;
    for (const std::string& a : allowed) listed += (listed.empty() ? "'" : ", '") + a + "'";
    throw InputError(option, "expected one of " + listed + ", got '" + value + "'");
}

void require_positive(const std::string& option, double value) {
    if (!(std::isfinite(value) && value > 0.0))
        throw InputError(option, "expected a positive number, got " + format_number(value));
}

}  // namespace

SimulationSettings settings_of(const SimulateArguments& a, const Model& model, std::vector<std::string>& messages) {
    require_positive("t_end", a.t_end);
    check_integrator_options(a.integrator, a.tol.has_value(), a.tol.value_or(0.0), a.step.has_value(),
                             a.step.value_or(0.0), a.t_end, python_spelling);
    if (a.output_step) output_intervals(a.t_end, *a.output_step, "output_step", "t_end");
    SimulationSettings s;
    s.formulation = a.formulation;
    s.integrator = a.integrator;
    if (a.tol) s.integration.tolerance = *a.tol;
    s.automatic_tolerance = !a.tol && !a.step;  // as `mbd simulate` without --tol (tolerance_choice.hpp)
    s.integration.step = a.step.value_or(0.0);
    s.t_end = a.t_end;
    s.output_step = a.output_step.value_or(0.0);
    s.reactions = a.reactions;
    s.diagnostics = a.diagnostics;
    if (a.stabilization) {
        require_one_of("stabilization", *a.stabilization, stabilization_names());
        s.stabilization = parse_stabilization(*a.stabilization);
    }
    if (a.linear_algebra) {
        try {
            s.algebra = parse_linear_algebra(*a.linear_algebra);
        } catch (const InputError& e) {
            throw InputError("linear_algebra", e.message());
        }
    }
    if (a.q0 || a.v0) {  // a start of the user's own, assembled and made consistent as the scene's
        State start = model.initial_state();
        if (a.q0) start.q = *a.q0;
        if (a.v0) start.v = *a.v0;
        if (start.q.size() != model.nq())
            throw InputError("q0", "expected " + std::to_string(model.nq()) + " coordinates, got " + std::to_string(start.q.size()));
        if (start.v.size() != model.nv())
            throw InputError("v0", "expected " + std::to_string(model.nv()) + " velocities, got " + std::to_string(start.v.size()));
        if (!start.q.allFinite() || !start.v.allFinite()) throw InputError(a.q0 ? "q0" : "v0", "expected finite numbers");
        s.initial_state = start;
    }
    s.progress = false;
    s.messages = MessageLog([&messages](const std::string& line) { messages.push_back(line); });
    return s;
}

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// CPU time of the calling thread (the engine runs a simulation in the thread that calls it).
double thread_cpu_seconds() {
    timespec now{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
    return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

py::dict run_statistics(const SimulationResult& r, double wall, double thread_cpu) {
    py::dict stats;
    stats["formulation"] = r.formulation;
    stats["integrator"] = r.integrator;
    stats["tolerance"] = r.tolerance;
    stats["rows"] = r.rows;
    stats["steps"] = r.stats.steps;
    stats["rejected_steps"] = r.stats.rejected_steps;
    stats["rhs_evaluations"] = r.stats.rhs_evaluations;
    stats["jacobian_evaluations"] = r.stats.jacobian_evaluations;
    stats["newton_iterations"] = r.stats.newton_iterations;
    stats["cpu_s"] = r.cpu_seconds;
    stats["wall_s"] = wall;
    stats["thread_cpu_s"] = thread_cpu;
    stats["position_violation"] = r.final_position_violation;
    stats["velocity_violation"] = r.final_velocity_violation;
    return stats;
}

// Forward dynamics: every output row (the CSV's columns), q and v at each, and the run's
// statistics. With `keep` false nothing is collected (the engine's own cost, for
// bench/python_overhead.py).
py::dict simulate_model(const ModelHandle& handle, const SimulateArguments& arguments, bool keep) {
    const Model& model = *handle.model;
    std::vector<std::string> messages;
    const SimulationSettings settings = with_scene_errors(handle, false, [&] { return settings_of(arguments, model, messages); });
    std::vector<double> rows, q, v;
    if (keep) {  // sized once: a reallocation touches fresh pages, which costs more than the copy
        const auto expected = static_cast<size_t>(simulation_rows(settings));
        rows.reserve(expected * (motion_columns(model).size() + (arguments.reactions ? reaction_columns(model).size() : 0) +
                                 (arguments.diagnostics ? diagnostic_columns().size() + 1 : 0)));
        q.reserve(expected * model.nq());
        v.reserve(expected * model.nv());
    }
    InterruptCheck interrupt;
    SimulationCallback collect = [&](const SimulationSample& sample) {
        rows.insert(rows.end(), sample.row->begin(), sample.row->end());
        q.insert(q.end(), sample.state.q.data(), sample.state.q.data() + sample.state.q.size());
        v.insert(v.end(), sample.state.v.data(), sample.state.v.data() + sample.state.v.size());
        interrupt();
        return true;
    };
    SimulationResult result;
    double wall = 0.0, thread_cpu = 0.0;
    {
        py::gil_scoped_release release;
        const auto start = std::chrono::steady_clock::now();
        const double cpu_start = thread_cpu_seconds();
        result = with_scene_errors(handle, false, [&] {
            return simulate(model, *handle.registry, settings, keep ? collect : SimulationCallback());
        });
        thread_cpu = thread_cpu_seconds() - cpu_start;
        wall = seconds_since(start);
    }
    py::dict out;
    const size_t n = keep ? static_cast<size_t>(result.rows) : 0;
    out["columns"] = result.columns;
    out["data"] = matrix_array(std::move(rows), n, result.columns.size());
    out["q"] = matrix_array(std::move(q), n, model.nq());
    out["v"] = matrix_array(std::move(v), n, model.nv());
    out["stats"] = run_statistics(result, wall, thread_cpu);
    out["messages"] = messages;
    return out;
}

// Static equilibrium: the report of `mbd statics --json` as JSON text, and q.
py::tuple statics_model(const ModelHandle& handle, double time, const std::string& objective,
                        const std::string& hessian, double tolerance, int max_iterations, const std::string& solver,
                        bool verbose) {
    StaticsOptions options;
    options.time = time;
    options.objective = objective;
    options.hessian = hessian;
    options.tolerance = tolerance;
    options.max_iterations = max_iterations;
    options.print_level = verbose ? 5 : 0;
    options.limits = scene_joint_limits(*handle.model);
    StaticsReport report;
    {
        py::gil_scoped_release release;
        report = with_scene_errors(handle, false, [&] { return run_statics(*handle.model, *handle.registry, options, solver); });
    }
    const std::string json = json_text(statics_json(*handle.model, report, options.limits));
    return py::make_tuple(json, vector_array(report.result.state.q));
}

// Inverse dynamics at t = 0, step, ..., t_end: the rows of `mbd inverse --output`.
py::dict inverse_model(const ModelHandle& handle, double t_end, double step, bool reactions, const std::string& solver) {
    const Model& model = *handle.model;
    with_scene_errors(handle, false, [&] { return output_intervals(t_end, step, "step", "t_end"); });
    const std::vector<std::string> columns = inverse_columns(model, reactions);
    std::vector<double> rows;
    size_t n = 0;
    InterruptCheck interrupt;
    {
        py::gil_scoped_release release;
        with_scene_errors(handle, false, [&] {
            run_inverse(model, *handle.registry, t_end, step, [&](const InverseSample& sample, System& system) {
                const std::vector<double> row = inverse_row(sample, system, reactions);
                rows.insert(rows.end(), row.begin(), row.end());
                ++n;
                interrupt();
                return true;
            }, InverseOptions{}, solver);
            return 0;
        });
    }
    py::dict out;
    out["columns"] = columns;
    out["data"] = matrix_array(std::move(rows), n, columns.size());
    return out;
}

// A result table as `mbd` writes one (csv.hpp, output_file.hpp): never one of `inputs`, under
// its name only when complete.
void write_csv(const std::string& path, const std::vector<std::string>& columns,
               const py::array_t<double, py::array::c_style | py::array::forcecast>& data,
               const std::vector<std::string>& inputs) {
    if (data.ndim() != 2 || static_cast<size_t>(data.shape(1)) != columns.size())
        throw InputError("data", "expected a table of " + std::to_string(columns.size()) + " columns");
    std::vector<std::filesystem::path> input_paths(inputs.begin(), inputs.end());
    check_output_path(path, input_paths, "path");
    const auto table = data.unchecked<2>();
    py::gil_scoped_release release;
    CsvWriter writer(path, columns);
    std::vector<double> row(columns.size());
    for (py::ssize_t r = 0; r < table.shape(0); ++r) {
        for (size_t c = 0; c < columns.size(); ++c) row[c] = table(r, static_cast<py::ssize_t>(c));
        writer.row(row);
    }
    writer.close();
}

}  // namespace

void bind_runs(py::module_& m) {
    py::class_<SimulateArguments>(m, "SimulateArguments")
        .def(py::init<>())
        .def_readwrite("t_end", &SimulateArguments::t_end)
        .def_readwrite("formulation", &SimulateArguments::formulation)
        .def_readwrite("integrator", &SimulateArguments::integrator)
        .def_readwrite("tol", &SimulateArguments::tol)
        .def_readwrite("step", &SimulateArguments::step)
        .def_readwrite("output_step", &SimulateArguments::output_step)
        .def_readwrite("reactions", &SimulateArguments::reactions)
        .def_readwrite("diagnostics", &SimulateArguments::diagnostics)
        .def_readwrite("stabilization", &SimulateArguments::stabilization)
        .def_readwrite("linear_algebra", &SimulateArguments::linear_algebra)
        .def_readwrite("q0", &SimulateArguments::q0)
        .def_readwrite("v0", &SimulateArguments::v0);
    m.def("integrators", [] {
        py::list rows;
        for (const IntegratorDescription& d : integrator_descriptions())
            rows.append(py::dict(py::arg("name") = d.name, py::arg("order") = d.order, py::arg("adaptive") = d.adaptive,
                                 py::arg("locates_events") = d.locates_events, py::arg("needs_index3") = d.needs_index3,
                                 py::arg("stiff") = d.stiff, py::arg("summary") = d.summary));
        return rows;
    }, "Every integrator as integrator.hpp's table describes it.");
    m.def("simulate", &simulate_model, py::arg("model"), py::arg("arguments"), py::arg("keep") = true);
    m.def("statics", &statics_model, py::arg("model"), py::arg("time"), py::arg("objective"), py::arg("hessian"),
          py::arg("tolerance"), py::arg("max_iterations"), py::arg("solver"), py::arg("verbose"));
    m.def("inverse", &inverse_model, py::arg("model"), py::arg("t_end"), py::arg("step"), py::arg("reactions"),
          py::arg("solver"));
    m.def("write_csv", &write_csv, py::arg("path"), py::arg("columns"), py::arg("data"), py::arg("inputs"));
}

}  // namespace mbd::python
