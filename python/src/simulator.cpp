// mbd.Simulator's engine (python/mbd/simulator.py wraps it; docs/python.md): a C++
// mbd::Simulator stepped with the GIL released, its state shown as read-only numpy arrays
// over a buffer of its own, and the Python callables it calls (a user force inside every
// right-hand side, an event callback) run with the GIL taken back.
#include "bindings.hpp"

#include <mbd/sdk/rotation.hpp>
#include <mbd/sdk/text.hpp>
#include <mbd/simulator.hpp>

#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include <cmath>
#include <stdexcept>

namespace mbd::python {

namespace {

// A read-only float64 vector over `values`, kept alive by `owner`.
py::array_t<double> read_only_view(Eigen::VectorXd& values, py::handle owner) {
    py::array_t<double> view(values.size(), values.data(), owner);
    py::detail::array_proxy(view.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
    return view;
}

class PySimulator {
public:
    PySimulator(const ModelHandle& handle, const SimulateArguments& arguments)
        : handle_(handle),
          simulator_(with_scene_errors(handle, false, [&] {
              const SimulationSettings settings = settings_of(arguments, *handle.model, messages_);
              py::gil_scoped_release release;
              return std::make_unique<Simulator>(*handle.model, *handle.registry, settings);
          })) {
        mirror();
    }

    // --- stepping, with the GIL released (the callbacks take it back)
    void step() {
        stepping([&] { simulator_->step(); });
    }
    void advance_to(double t) {
        stepping([&] { simulator_->advance_to(t); });
    }
    void reset(std::optional<double> t, std::optional<Eigen::VectorXd> q, std::optional<Eigen::VectorXd> v) {
        stepping([&] {
            if (!t && !q && !v) return simulator_->reset();
            State start = simulator_->state();
            if (t) start.t = *t;
            if (q) start.q = *q;
            if (v) start.v = *v;
            simulator_->reset(start);
        });
    }

    double time() const { return simulator_->state().t; }
    py::array_t<double> q(py::object self) { return read_only_view(q_, self); }
    py::array_t<double> v(py::object self) { return read_only_view(v_, self); }

    // --- by name
    py::tuple body_state(const std::string& body) const {
        return py::make_tuple(vector_array(simulator_->body_coordinates(body)), vector_array(simulator_->body_velocities(body)));
    }
    void set_body_state(const std::string& body, const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
        stepping([&] { simulator_->set_body_state(body, q, v); });
    }

    py::tuple joint_state(const std::string& joint) const {
        return py::make_tuple(simulator_->joint_coordinate(joint), simulator_->joint_rate(joint));
    }
    void set_joint_state(const std::string& joint, double coordinate, double rate) {
        stepping([&] { simulator_->set_joint_state(joint, coordinate, rate); });
    }

    // --- inputs
    void set_input(const std::string& name, double value) { simulator_->set_input(name, value); }
    double input(const std::string& name) const { return simulator_->input(name); }
    std::vector<std::string> input_names() const { return simulator_->input_names(); }

    // --- the user force: callable(t, q, v) giving generalized forces ("generalized") or one
    // row per body ("bodies"). None removes it.
    void set_user_force(py::object callable, const std::string& kind) {
        if (kind != "generalized" && kind != "bodies")
            throw InputError("kind", "expected 'generalized' or 'bodies', got '" + kind + "'");
        if (callable.is_none()) return simulator_->set_user_force(nullptr);
        if (!PyCallable_Check(callable.ptr())) throw InputError("force", "expected a callable f(t, q, v)");
        const bool bodies = kind == "bodies";
        simulator_->set_user_force([this, callable, bodies](const State& s) -> Eigen::VectorXd {
            py::gil_scoped_acquire hold;
            return user_force(callable, bodies, s);
        });
    }
    void on_event(py::object callable) {
        if (callable.is_none()) return simulator_->on_event(nullptr);
        simulator_->on_event([callable](const EventRecord& e) {
            py::gil_scoped_acquire hold;
            callable(event_dict(e));
        });
    }
    py::list events() const {
        py::list out;
        for (const EventRecord& e : simulator_->events()) out.append(event_dict(e));
        return out;
    }

    // The Python exception the user force raised in the last failed step (its traceback on
    // it), once; None when there is none.
    py::object take_callback_error() {
        py::object error = callback_error_;
        callback_error_ = py::none();
        return error;
    }

    py::dict info() const {
        py::dict out;
        out["formulation"] = simulator_->formulation();
        out["integrator"] = simulator_->integrator();
        out["tolerance"] = simulator_->tolerance();
        out["messages"] = messages_;
        return out;
    }
    py::dict stats() const {
        const IntegratorStats& s = simulator_->stats();
        py::dict out;
        out["steps"] = s.steps;
        out["rejected_steps"] = s.rejected_steps;
        out["rhs_evaluations"] = s.rhs_evaluations;
        out["jacobian_evaluations"] = s.jacobian_evaluations;
        out["newton_iterations"] = s.newton_iterations;
        return out;
    }

private:
    static py::dict event_dict(const EventRecord& e) {
        py::dict d;
        d["time"] = e.time;
        d["force"] = e.force;
        d["event"] = e.event;
        d["kind"] = e.kind;
        d["rate_before"] = e.rate_before;
        d["rate_after"] = e.rate_after;
        return d;
    }

    template <class Work>
    void stepping(Work&& work) {
        callback_error_ = py::none();
        with_scene_errors(handle_, false, [&] {
            py::gil_scoped_release release;
            work();
            return 0;
        });
        mirror();
    }

    // The state into the buffer the arrays q and v show (a formulation may give the State
    // new storage; the buffer keeps its own).
    void mirror() {
        q_ = simulator_->state().q;
        v_ = simulator_->state().v;
    }

    Eigen::VectorXd user_force(const py::object& callable, bool bodies, const State& s) {
        py::object result;
        try {
            result = callable(s.t, vector_array(s.q), vector_array(s.v));
        } catch (py::error_already_set& e) {
            callback_error_ = e.value();
            if (e.trace()) PyException_SetTraceback(callback_error_.ptr(), e.trace().ptr());
            const std::string type = py::str(e.type().attr("__name__"));
            const std::string text = py::str(e.value());
            throw std::runtime_error("the Python callable raised " + type + (text.empty() ? "" : ": " + text));
        }
        return bodies ? from_body_forces(result, s) : from_generalized(result);
    }

    Eigen::VectorXd from_generalized(const py::object& result) const {
        const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(result);
        const int nv = handle_.model->nv();
        if (!a || a.ndim() != 1 || a.shape(0) != nv)
            throw std::runtime_error("the Python callable returned " + shape_of(result) + "; it must return " +
                                     std::to_string(nv) + " generalized forces (a vector of shape (" +
                                     std::to_string(nv) + ",), in the order of v)");
        return Eigen::Map<const Eigen::VectorXd>(a.data(), nv);
    }

    // One row per body, in the model's order: planar (fx, fy, torque); spatial (force, moment),
    // both in world axes at the mass centre. The moment becomes the body-frame moment that is
    // the generalized force of omega_bar.
    Eigen::VectorXd from_body_forces(const py::object& result, const State& s) const {
        const Model& m = *handle_.model;
        const int n = m.body_count(), per = velocities_per_body(m.dimension);
        const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(result);
        if (!a || a.ndim() != 2 || a.shape(0) != n || a.shape(1) != per)
            throw std::runtime_error("the Python callable returned " + shape_of(result) + "; it must return one row per body, shape (" +
                                     std::to_string(n) + ", " + std::to_string(per) + ")" +
                                     (per == 3 ? ": fx, fy, torque" : ": force and moment in world axes"));
        Eigen::VectorXd Q = Eigen::Map<const Eigen::VectorXd>(a.data(), n * per);
        if (per == 6)
            for (int b = 0; b < n; ++b) {
                const Vec4 p = s.q.segment<4>(m.q_offset(b) + 3);
                Q.segment<3>(m.v_offset(b) + 3) = rotation_from_euler_parameters(p).transpose() * Q.segment<3>(m.v_offset(b) + 3);
            }
        return Q;
    }

    static std::string shape_of(const py::object& value) {
        if (py::hasattr(value, "shape")) return "shape " + py::str(value.attr("shape")).cast<std::string>();
        if (value.is_none()) return "None";
        return "a " + py::str(py::type::of(value).attr("__name__")).cast<std::string>();
    }

    ModelHandle handle_;  // keeps the model and its registry alive
    std::vector<std::string> messages_;
    std::unique_ptr<Simulator> simulator_;
    Eigen::VectorXd q_, v_;
    py::object callback_error_ = py::none();
};

}  // namespace

void bind_simulator(py::module_& m) {
    py::class_<PySimulator>(m, "Simulator", "The engine of mbd.Simulator, which wraps it.")
        .def(py::init<const ModelHandle&, const SimulateArguments&>(), py::arg("model"), py::arg("arguments"))
        .def("step", &PySimulator::step)
        .def("advance_to", &PySimulator::advance_to, py::arg("t"))
        .def("reset", &PySimulator::reset, py::arg("t"), py::arg("q"), py::arg("v"))
        .def("time", &PySimulator::time)
        .def("q", [](py::object self) { return self.cast<PySimulator&>().q(self); })
        .def("v", [](py::object self) { return self.cast<PySimulator&>().v(self); })
        .def("body_state", &PySimulator::body_state, py::arg("body"))
        .def("set_body_state", &PySimulator::set_body_state, py::arg("body"), py::arg("q"), py::arg("v"))
        .def("joint_state", &PySimulator::joint_state, py::arg("joint"))
        .def("set_joint_state", &PySimulator::set_joint_state, py::arg("joint"), py::arg("coordinate"), py::arg("rate"))
        .def("set_input", &PySimulator::set_input, py::arg("name"), py::arg("value"))
        .def("input", &PySimulator::input, py::arg("name"))
        .def("input_names", &PySimulator::input_names)
        .def("set_user_force", &PySimulator::set_user_force, py::arg("callable"), py::arg("kind"))
        .def("on_event", &PySimulator::on_event, py::arg("callable"))
        .def("events", &PySimulator::events)
        .def("take_callback_error", &PySimulator::take_callback_error)
        .def("info", &PySimulator::info)
        .def("stats", &PySimulator::stats);
}

}  // namespace mbd::python
