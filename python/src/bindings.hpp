// The pieces of the extension mbd._mbd shared by its files (docs/python.md). The extension
// is thin: it turns Python arguments into the engine's settings, runs the engine with the
// GIL released, and hands back numbers, arrays and JSON text; the Python package around it
// (python/mbd/) gives them their Python shape.
#pragma once

#include <mbd/model.hpp>
#include <mbd/registry.hpp>
#include <mbd/simulation.hpp>
#include <mbd/sdk/params.hpp>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace mbd::python {

namespace py = pybind11;

// A Model as Python holds it: immutable and shared by every thread that runs it (each run
// makes its own Data), with the registry its elements came from, which also makes its
// formulations and solvers.
struct ModelHandle {
    std::shared_ptr<const Model> model;
    std::shared_ptr<Registry> registry;
    bool from_dict = false;  // its document came from Model.from_dict: "lines" are node numbers
};

// The registry of the plugin path in force (set_plugin_path); models keep the one they were
// loaded with.
std::shared_ptr<Registry> current_registry();

// `error` as the Python exception it becomes: PluginError; SceneError when it is about a
// scene (`reading_scene`, a location with a line or that is the scene's file, or a
// ParameterError, whose path is its key),
// with its file, line and the key at that location in `document` (when null, the scene file is
// read again for it); otherwise InputError (an option of a run). In a document from a dict
// (`from_dict`), node numbers stand for lines: the message names keys instead.
[[noreturn]] void rethrow_scene_error(const InputError& error, const Param* document, bool from_dict,
                                      bool reading_scene);

// Runs `work`, passing its InputError through rethrow_scene_error against the model's document.
template <class Work>
auto with_scene_errors(const ModelHandle& handle, bool reading_scene, Work&& work) {
    try {
        return work();
    } catch (const InputError& e) {
        rethrow_scene_error(e, handle.model->document.get(), handle.from_dict, reading_scene);
    }
}

// The keyword arguments of Model.simulate, as the engine's settings (the rules of
// `mbd simulate`: check_integrator_options, output_intervals).
struct SimulateArguments {
    double t_end = 0.0;
    std::string formulation, integrator;
    std::optional<double> tol, step, output_step;
    bool reactions = false, diagnostics = false;
    std::optional<std::string> stabilization, linear_algebra;
    std::optional<Eigen::VectorXd> q0, v0;
};
// The arguments as the engine's settings (runs.cpp); the run's messages go to `messages`,
// which must outlive the settings.
SimulationSettings settings_of(const SimulateArguments& arguments, const Model& model, std::vector<std::string>& messages);

// A float64 numpy array of `rows` x `columns` that takes over `values` (no copy).
py::array_t<double> matrix_array(std::vector<double>&& values, size_t rows, size_t columns);
// A float64 numpy vector holding a copy of `values`.
py::array_t<double> vector_array(const Eigen::VectorXd& values);

// Checks for Ctrl-C between output samples of a run on the main thread (at most every 50 ms):
// raises KeyboardInterrupt through the engine, which unwinds its run cleanly.
class InterruptCheck {
public:
    InterruptCheck();
    void operator()();

private:
    bool main_thread_;
    double next_ = 0.0;
};

void bind_errors(py::module_& m);
void bind_plugins(py::module_& m);
void bind_model(py::module_& m);
void bind_runs(py::module_& m);
void bind_analyses(py::module_& m);
void bind_simulator(py::module_& m);  // simulator.cpp: mbd.Simulator's engine  // analyses.cpp: modes, kinematics, the viewer page

}  // namespace mbd::python
