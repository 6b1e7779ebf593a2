// Models from scene files and from Python dicts, changed models (with_params), and what a
// model holds (info, check).
#include "bindings.hpp"

#include <mbd/import/import.hpp>
#include <mbd/scene.hpp>
#include <mbd/scene_check.hpp>
#include <mbd/scene_parameters.hpp>
#include <mbd/sdk/text.hpp>

#include <pybind11/stl.h>

#include <cmath>

namespace mbd::python {

namespace {

// A Python value (dicts, lists and tuples of numbers, strings, booleans and None, numpy arrays
// and scalars) as the Param tree a scene file reads into, within the scene reader's limits.
// Each node is numbered where a file gives a line (file = `label`): messages name the node,
// and rethrow_scene_error writes it as its key.
class DictReader {
public:
    explicit DictReader(std::string label) : label_(std::move(label)) {}

    Param read(const py::handle& value) { return convert(value, "", 0); }

private:
    [[noreturn]] void fail(const std::string& path, const std::string& message) const {
        throw ParameterError(label_, (path.empty() ? "" : "key '" + path + "': ") + message, path);
    }

    Param node(Param::Kind kind) {
        Param p;
        p.kind = kind;
        p.file = label_;
        p.line = ++nodes_;
        if (static_cast<std::size_t>(nodes_) > SceneLimits::max_values)
            fail("", "the scene has more than " + std::to_string(SceneLimits::max_values) + " values");
        return p;
    }

    Param convert(py::handle value, const std::string& path, int depth) {
        if (depth > SceneLimits::max_depth)
            fail(path, "lists and dicts are nested more than " + std::to_string(SceneLimits::max_depth) +
                           " levels deep (does a dict contain itself?)");
        if (py::hasattr(value, "tolist") && !py::isinstance<py::str>(value)) {  // numpy arrays and scalars
            const py::object plain = value.attr("tolist")();
            return convert(plain, path, depth);
        }
        if (py::isinstance<py::dict>(value)) {
            Param map = node(Param::Kind::Map);
            for (const auto& [key, item] : py::reinterpret_borrow<py::dict>(value)) {
                if (!py::isinstance<py::str>(key))
                    fail(path, "a key must be a string, got " + std::string(py::str(py::repr(key))));
                const std::string name = key.cast<std::string>();
                map.fields.emplace(name, convert(item, path.empty() ? name : path + "." + name, depth + 1));
            }
            return map;
        }
        if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
            Param list = node(Param::Kind::List);
            size_t index = 0;
            for (const py::handle item : value)
                list.items.push_back(convert(item, path + "[" + std::to_string(index++) + "]", depth + 1));
            return list;
        }
        Param scalar = node(Param::Kind::Scalar);
        if (value.is_none()) return scalar;  // as YAML's null: an empty scalar
        if (py::isinstance<py::bool_>(value)) {
            scalar.text = value.cast<bool>() ? "true" : "false";
        } else if (py::isinstance<py::int_>(value) || py::isinstance<py::float_>(value) ||
                   py::isinstance<py::str>(value)) {
            // a float's repr is the shortest text that reads back to the same double
            scalar.text = py::isinstance<py::str>(value) ? value.cast<std::string>() : std::string(py::repr(value));
        } else {
            fail(path, "expected a number, a string, a list or a dict, got " +
                           std::string(py::str(value.get_type().attr("__name__"))));
        }
        return scalar;
    }

    std::string label_;
    int nodes_ = 0;
};

ModelHandle made(Model model, std::shared_ptr<Registry> registry, bool from_dict) {
    return ModelHandle{std::make_shared<const Model>(std::move(model)), std::move(registry), from_dict};
}

// A scene file, or a model file (MJCF, URDF, SDF: known from its content) imported as `mbd import`
// does with its default options (docs/import.md); the second item is the import's one-line list of
// what it left out ("" when nothing), which the Python side warns with.
std::pair<ModelHandle, std::string> load(const std::string& path) {
    std::shared_ptr<Registry> registry = current_registry();
    py::gil_scoped_release release;
    std::string left_out;
    try {
        Model model = import::load_scene_or_model(path, *registry, [&](const std::string& w) { left_out = w; });
        return {made(std::move(model), registry, false), left_out};
    } catch (const InputError& e) {
        rethrow_scene_error(e, nullptr, false, true);
    }
}

ModelHandle from_dict(const py::dict& scene, const std::string& label) {
    Param document;
    try {
        document = DictReader(label).read(scene);
    } catch (const InputError& e) {
        rethrow_scene_error(e, nullptr, true, true);
    }
    std::shared_ptr<Registry> registry = current_registry();
    py::gil_scoped_release release;
    try {
        return made(load_scene_document(document, label, *registry), registry, true);
    } catch (const InputError& e) {
        rethrow_scene_error(e, &document, true, true);
    }
}

ModelHandle with_params(const ModelHandle& handle, const SceneParameterValues& values) {
    py::gil_scoped_release release;
    return with_scene_errors(handle, true, [&] {
        return made(with_scene_parameters(*handle.model, values, *handle.registry), handle.registry, handle.from_dict);
    });
}

double param(const ModelHandle& handle, const std::string& path) {
    return with_scene_errors(handle, true, [&] { return scene_parameter(*handle.model->document, path); });
}

std::vector<std::string> names(const std::vector<int>& bodies, const Model& model) {
    std::vector<std::string> out;
    for (int b : bodies) out.push_back(model.body_name(b));
    return out;
}

template <class Elements>
py::list element_list(const Elements& elements, const Model& model) {
    py::list out;
    for (const auto& e : elements) {
        py::dict item;
        item["name"] = e.name;
        item["type"] = e.type;
        item["bodies"] = names(e.bodies, model);
        item["where"] = e.where;
        out.append(item);
    }
    return out;
}

py::dict info(const ModelHandle& handle) {
    const Model& model = *handle.model;
    py::dict out;
    out["name"] = model.name;
    out["source"] = model.source;
    out["base_files"] = model.base_files;
    out["dimension"] = to_string(model.dimension);
    out["formulation"] = model.formulation;
    out["nq"] = model.nq();
    out["nv"] = model.nv();
    const State start = model.initial_state();
    out["q0"] = vector_array(start.q);
    out["v0"] = vector_array(start.v);
    py::list bodies;
    for (const Body& b : model.bodies) {
        py::dict body;
        body["name"] = b.name;
        body["mass"] = b.mass;
        body["where"] = b.where;
        bodies.append(body);
    }
    out["bodies"] = bodies;
    out["joints"] = element_list(model.joints, model);
    out["forces"] = element_list(model.forces, model);
    py::list drivers, actuators;
    for (const Driver& d : model.drivers) drivers.append(py::dict(py::arg("name") = d.name, py::arg("joint") = model.joints[d.joint].name));
    for (const Actuator& a : model.actuators)
        actuators.append(py::dict(py::arg("name") = a.name, py::arg("joint") = model.joints[a.joint].name));
    out["drivers"] = drivers;
    out["actuators"] = actuators;
    return out;
}

py::dict check(const ModelHandle& handle, double rank_tolerance) {
    if (!(rank_tolerance >= 1e-16 && rank_tolerance <= 1.0))
        throw InputError("rank_tolerance", "expected a number from 1e-16 to 1, got " + format_number(rank_tolerance));
    SceneCheck c;
    {
        py::gil_scoped_release release;
        c = check_scene(*handle.model, rank_tolerance);
    }
    py::dict out;
    out["assembly_iterations"] = c.assembly.iterations;
    out["assembly_residual"] = c.assembly.residual;
    out["q"] = vector_array(c.assembled.q);
    out["velocities"] = c.mobility.coordinates;
    out["joint_equations"] = c.mobility.constraint_rows;
    out["driver_equations"] = c.mobility.driver_rows;
    out["gruebler_dof"] = c.mobility.gruebler_dof;
    out["rank"] = c.mobility.rank;
    out["rank_dof"] = c.mobility.rank_dof;
    std::vector<std::string> redundant;
    for (const RowOwner& o : c.mobility.redundant) redundant.push_back(o.describe());
    out["redundant"] = redundant;
    out["full_rank"] = c.full_rank;
    out["free_dof"] = c.free_dof;
    out["dependent_driver_rows"] = c.dependent_driver_rows;
    out["kinematically_driven"] = c.kinematically_driven;
    out["embedding"] = c.embedding.path;
    out["embedding_reason"] = c.embedding.reason;
    return out;
}

}  // namespace

void bind_model(py::module_& m) {
    py::class_<ModelHandle>(m, "Model", "A model of the engine (immutable); use mbd.Model, which wraps it.")
        .def("with_params", &with_params, py::arg("values"))
        .def("param", &param, py::arg("path"))
        .def("info", &info)
        .def("check", &check, py::arg("rank_tolerance"));
    m.def("load", &load, py::arg("path"), "The model of a scene or model (MJCF, URDF, SDF) file, and what its import left out.");
    m.def("from_dict", &from_dict, py::arg("scene"), py::arg("label"), "The model of a scene given as dicts.");
}

}  // namespace mbd::python
