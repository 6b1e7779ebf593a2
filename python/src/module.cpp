// The extension module mbd._mbd (docs/python.md), and the helpers its files share.
#include "bindings.hpp"

#include <mbd/app/scene_sections.hpp>

#include <pythread.h>

#include <chrono>

namespace mbd::python {

namespace {

unsigned long main_thread_id = 0;  // Python's main thread: the one that handles signals

double seconds_now() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

py::array_t<double> matrix_array(std::vector<double>&& values, size_t rows, size_t columns) {
    auto* owned = new std::vector<double>(std::move(values));
    py::capsule owner(owned, [](void* p) { delete static_cast<std::vector<double>*>(p); });
    const auto row_bytes = static_cast<py::ssize_t>(columns * sizeof(double));
    return py::array_t<double>({static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(columns)},
                               {row_bytes, static_cast<py::ssize_t>(sizeof(double))}, owned->data(), owner);
}

py::array_t<double> vector_array(const Eigen::VectorXd& values) {
    return py::array_t<double>(values.size(), values.data());
}

InterruptCheck::InterruptCheck() : main_thread_(PyThread_get_thread_ident() == main_thread_id) {}

void InterruptCheck::operator()() {
    if (!main_thread_) return;
    const double now = seconds_now();
    if (now < next_) return;
    next_ = now + 0.05;
    py::gil_scoped_acquire hold;
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
}

}  // namespace mbd::python

PYBIND11_MODULE(_mbd, m) {
    namespace mp = mbd::python;
    namespace py = pybind11;
    m.doc() = "The engine of mbd (multibody dynamics); import mbd, the package around it.";
    m.attr("version") = MBD_VERSION;
    mp::main_thread_id = py::module_::import("threading").attr("main_thread")().attr("ident").cast<unsigned long>();
    mbd::declare_application_scene_sections();  // a scene with `bench:` or `expect:` loads here as in mbd
    mp::bind_errors(m);
    mp::bind_plugins(m);
    mp::bind_model(m);
    mp::bind_runs(m);
    mp::bind_analyses(m);
    mp::bind_simulator(m);
}
