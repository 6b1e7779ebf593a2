// Modes and kinematics of a model from Python, computed by the functions behind `mbd modes`
// and `mbd kinematics` (study_modes, run_kinematics) so that the numbers are the command's to
// the bit; and the offline viewer page of a result, as `mbd animate` writes it.
#include "bindings.hpp"

#include <mbd/app/modes_json.hpp>
#include <mbd/csv.hpp>
#include <mbd/kinematics.hpp>
#include <mbd/linearisation.hpp>
#include <mbd/linear_algebra.hpp>
#include <mbd/modes_study.hpp>
#include <mbd/output_times.hpp>
#include <mbd/sdk/text.hpp>
#include <mbd/viewer/animation_export.hpp>

#include <pybind11/stl.h>

#include <cmath>
#include <sstream>

namespace mbd::python {

namespace {

// The report of `mbd modes --json` as JSON text, or the statics' failure (converged false and
// its message: no modes).
py::tuple modes_model(const ModelHandle& handle, const std::string& about, double residual_tolerance,
                      const std::string& solver, int statics_iterations) {
    ModesStudyOptions options;
    options.about = about;
    options.residual_tolerance = residual_tolerance;
    options.solver = solver;
    options.statics_iterations = statics_iterations;
    if (!(std::isfinite(residual_tolerance) && residual_tolerance > 0.0))
        throw InputError("residual_tolerance", "expected a positive number, got " + format_number(residual_tolerance));
    if (statics_iterations < 1)
        throw InputError("statics_iterations", "expected a positive number, got " + std::to_string(statics_iterations));
    ModesStudy study;
    {
        py::gil_scoped_release release;
        study = with_scene_errors(handle, false, [&] { return study_modes(*handle.model, *handle.registry, options); });
    }
    if (!study.statics_converged) return py::make_tuple(false, study.statics_message, "");
    return py::make_tuple(true, "", json_text(modes_json(about, study.linear, study.analysis)));
}

// Kinematically driven motion at t = 0, step, ..., t_end: the rows of `mbd kinematics --output`.
py::dict kinematics_model(const ModelHandle& handle, double t_end, double step, double tolerance, int max_iterations,
                          const std::string& linear_algebra) {
    const Model& model = *handle.model;
    with_scene_errors(handle, false, [&] { return output_intervals(t_end, step, "step", "t_end"); });
    if (!(tolerance >= 1e-15 && tolerance <= 1.0))  // the range of `mbd kinematics --tolerance`
        throw InputError("tolerance", "expected a number from 1e-15 to 1 (smaller is beneath double-precision "
                                      "round-off), got " + format_number(tolerance));
    if (max_iterations < 1)
        throw InputError("max_iterations", "expected a positive number, got " + std::to_string(max_iterations));
    KinematicsOptions options;
    options.newton.tolerance = tolerance;
    options.newton.max_iterations = max_iterations;
    try {
        options.newton.algebra = parse_linear_algebra(linear_algebra);
    } catch (const InputError& e) {
        throw InputError("linear_algebra", e.message());
    }
    const std::vector<std::string> columns = motion_columns(model);
    std::vector<double> rows;
    size_t n = 0;
    InterruptCheck interrupt;
    {
        py::gil_scoped_release release;
        with_scene_errors(handle, false, [&] {
            run_kinematics(model, t_end, step, [&](const State& state, const Eigen::VectorXd&) {
                const std::vector<double> row = motion_values(model, state);
                rows.insert(rows.end(), row.begin(), row.end());
                ++n;
                interrupt();
                return true;
            }, options);
            return 0;
        });
    }
    py::dict out;
    out["columns"] = columns;
    out["data"] = matrix_array(std::move(rows), n, columns.size());
    return out;
}

// The self-contained viewer page of a result table (columns t, then the bodies' poses, as
// `mbd simulate` writes them), as `mbd animate RESULT.csv -o out.html` writes it.
std::string viewer_page(const ModelHandle& handle, const std::vector<std::string>& columns,
                        const py::array_t<double, py::array::c_style | py::array::forcecast>& data,
                        const std::string& plot_column) {
    if (data.ndim() != 2 || static_cast<size_t>(data.shape(1)) != columns.size() || data.shape(0) < 1)
        throw InputError("data", "expected a table of at least one row and " + std::to_string(columns.size()) + " columns");
    viewer::MotionTable table;
    table.source = "<result>";
    table.columns = columns;
    table.values.assign(data.data(), data.data() + data.size());
    viewer::AnimationOptions options;
    options.plot_column = plot_column;
    std::ostringstream page;
    py::gil_scoped_release release;
    with_scene_errors(handle, false, [&] {
        viewer::write_html(*handle.model, table, options, page);
        return 0;
    });
    return page.str();
}

}  // namespace

void bind_analyses(py::module_& m) {
    // a scene whose equations cannot be linearised (no freedom, a reference that accelerates):
    // mbd.LinearisationError with the message `mbd modes` prints
    py::register_exception_translator([](std::exception_ptr thrown) {
        try {
            if (thrown) std::rethrow_exception(thrown);
        } catch (const LinearisationError& e) {
            try {
                py::object type = py::module_::import("mbd.errors").attr("LinearisationError");
                PyErr_SetObject(type.ptr(), type(e.what()).ptr());
            } catch (const py::error_already_set&) {  // the extension used without its package
                PyErr_SetString(PyExc_RuntimeError, e.what());
            }
        }
    });
    m.def("modes", &modes_model, py::arg("model"), py::arg("about"), py::arg("residual_tolerance"), py::arg("solver"),
          py::arg("statics_iterations"));
    m.def("kinematics", &kinematics_model, py::arg("model"), py::arg("t_end"), py::arg("step"), py::arg("tolerance"),
          py::arg("max_iterations"), py::arg("linear_algebra"));
    m.def("viewer_page", &viewer_page, py::arg("model"), py::arg("columns"), py::arg("data"), py::arg("plot_column"));
}

}  // namespace mbd::python
