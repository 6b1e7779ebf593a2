// The engine's errors as Python exceptions (python/mbd/errors.py), each carrying the message
// `mbd` prints after "mbd: error: ".
#include "bindings.hpp"

#include <mbd/interrupt.hpp>
#include <mbd/kinematics.hpp>
#include <mbd/output_file.hpp>
#include <mbd/scene_parameters.hpp>
#include <mbd/kit/formulation.hpp>
#include <mbd/sdk/text.hpp>

#include <cctype>
#include <cmath>
#include <optional>

namespace mbd::python {

namespace {

// A C++ error on its way to Python: the class in mbd.errors and its arguments.
struct Failure {
    std::string kind;  // SceneError, PluginError, InputError
    std::string message, file, key;
    int line = 0;
};

struct Location {
    std::string file;
    int line = 0;
};

// "file:line" -> (file, line); anything else is a file (or an option) without a line.
Location parse_location(const std::string& where) {
    const size_t colon = where.rfind(':');
    if (colon != std::string::npos && colon + 1 < where.size() && colon > 0) {
        bool digits = true;
        for (size_t k = colon + 1; k < where.size(); ++k) digits = digits && std::isdigit(static_cast<unsigned char>(where[k]));
        if (digits && where.size() - colon <= 10) return {where.substr(0, colon), std::stoi(where.substr(colon + 1))};
    }
    return {where, 0};
}

// In a document from a dict, node numbers stand where a file has lines: every "LABEL:N" and
// "at line N" of the message becomes the key of node N.
std::string with_keys_for_lines(std::string message, const Param& document) {
    const std::string label = document.file;
    auto key_of = [&](int node) { return scene_key_at(document, label, node); };
    auto replace_numbers = [&](const std::string& prefix, const std::string& before_key) {
        size_t at = 0;
        while ((at = message.find(prefix, at)) != std::string::npos) {
            size_t end = at + prefix.size();
            while (end < message.size() && std::isdigit(static_cast<unsigned char>(message[end]))) ++end;
            const std::string number = message.substr(at + prefix.size(), end - at - prefix.size());
            const std::string key = number.empty() || number.size() > 9 ? std::string() : key_of(std::stoi(number));
            if (key.empty()) {
                at = end;
                continue;
            }
            const std::string text = before_key + "key '" + key + "'";
            message.replace(at, end - at, text);
            at += text.size();
        }
    };
    replace_numbers(label + ":", label + ": ");
    replace_numbers("at line ", "at ");
    return message;
}

}  // namespace

void rethrow_scene_error(const InputError& error, const Param* document, bool from_dict, bool reading_scene) {
    if (dynamic_cast<const OutputError*>(&error)) throw;
    const Location at = parse_location(error.where());
    Failure f{"InputError", error.what(), at.file, "", at.line};
    if (dynamic_cast<const PluginError*>(&error)) f.kind = "PluginError";
    else if (reading_scene || at.line > 0 || (document && at.file == document->file)) f.kind = "SceneError";
    if (const auto* parameter = dynamic_cast<const ParameterError*>(&error)) {
        f.kind = "SceneError";
        f.key = parameter->path();
    }
    std::optional<Param> read;  // a scene file that failed to build: its document, read again for the key
    if (!document && at.line > 0 && !from_dict) {
        try {
            read = read_scene_document(at.file);
            document = &*read;
        } catch (const InputError&) {  // no document (not YAML): no key to name
        }
    }
    if (document && f.key.empty() && at.line > 0) f.key = scene_key_at(*document, at.file, at.line);
    if (document && from_dict && at.file == document->file) {
        f.message = with_keys_for_lines(f.message, *document);
        f.line = 0;
    }
    throw f;
}

namespace {

// Sets the Python error: mbd.errors.KIND(message, **arguments); RuntimeError when the
// package cannot be imported (the extension used on its own).
void raise(const char* kind, const std::string& message, const py::dict& arguments) {
    try {
        py::object type = py::module_::import("mbd.errors").attr(kind);
        py::object error = type(message, **arguments);
        PyErr_SetObject(type.ptr(), error.ptr());
    } catch (const py::error_already_set&) {
        PyErr_SetString(PyExc_RuntimeError, message.c_str());
    }
}

py::object text_or_none(const std::string& text) { return text.empty() ? py::none() : py::object(py::str(text)); }

void raise_failure(const Failure& f) {
    py::dict arguments;
    if (f.kind == "InputError") {
        arguments["where"] = text_or_none(f.file);
    } else {
        arguments["file"] = text_or_none(f.file);
        arguments["line"] = f.line > 0 ? py::object(py::int_(f.line)) : py::none();
        arguments["key"] = text_or_none(f.key);
    }
    raise(f.kind.c_str(), f.message, arguments);
}

}  // namespace

void bind_errors(py::module_&) {
    py::register_exception_translator([](std::exception_ptr thrown) {
        try {
            if (thrown) std::rethrow_exception(thrown);
        } catch (const Failure& f) {
            raise_failure(f);
        } catch (const OutputError& e) {
            py::dict arguments;
            arguments["where"] = text_or_none(e.where());
            raise("OutputError", e.what(), arguments);
        } catch (const InputError& e) {
            try {
                rethrow_scene_error(e, nullptr, false, false);
            } catch (const Failure& f) {
                raise_failure(f);
            }
        } catch (const DynamicsError& e) {
            // as `mbd` prints it: the time first, when the failure has one
            py::dict arguments;
            arguments["time"] = std::isfinite(e.time()) ? py::object(py::float_(e.time())) : py::none();
            raise("DynamicsError",
                  (std::isfinite(e.time()) ? "at t = " + format_time(e.time()) + ": " : std::string()) + e.what(),
                  arguments);
        } catch (const KinematicsError& e) {
            raise("KinematicsError", e.what(), py::dict());
        } catch (const Interrupted& e) {
            PyErr_SetString(PyExc_KeyboardInterrupt, ("stopped by " + e.signal_name()).c_str());
        }
    });
}

}  // namespace mbd::python
