// The plugin path and the plugins found in it (mbd.plugins(), mbd.set_plugin_path()).
#include "bindings.hpp"

#include <pybind11/stl.h>

#include <filesystem>
#include <mutex>
#include <optional>

namespace mbd::python {

namespace {

std::mutex registry_mutex;
std::shared_ptr<Registry> registry;  // made on first use: the default search path then

std::vector<std::string> path_strings(const std::vector<std::filesystem::path>& folders) {
    std::vector<std::string> out;
    for (const auto& folder : folders) out.push_back(folder.string());
    return out;
}

// A new registry over `folders` (None: the default path), which later loads use; models loaded
// before keep theirs. A folder that does not exist is refused, as a typo would otherwise only
// show up as an unknown type.
void set_plugin_path(const std::optional<std::vector<std::string>>& folders) {
    std::vector<std::filesystem::path> path;
    if (folders) {
        for (const std::string& folder : *folders) {
            if (!std::filesystem::is_directory(folder))
                throw PluginError(folder, "no such plugin folder (give folders that hold plugin libraries)");
            path.emplace_back(folder);
        }
    } else {
        path = Registry::default_search_path();
    }
    auto made = std::make_shared<Registry>(path);
    const std::lock_guard<std::mutex> lock(registry_mutex);
    registry = std::move(made);
}

py::list plugin_types() {
    py::list out;
    for (const PluginType& t : current_registry()->types()) {
        py::dict type;
        type["kind"] = t.kind;
        type["type"] = t.type;
        type["abi"] = t.abi;
        type["library"] = t.library.string();
        type["version"] = t.version;
        type["usable"] = t.abi == host_abi(t.kind);
        out.append(type);
    }
    return out;
}

}  // namespace

std::shared_ptr<Registry> current_registry() {
    const std::lock_guard<std::mutex> lock(registry_mutex);
    if (!registry) registry = std::make_shared<Registry>();
    return registry;
}

void bind_plugins(py::module_& m) {
    m.def("plugin_types", &plugin_types, "Every plugin type of the plugin path: kind, type, abi, library, version, usable.");
    m.def("plugin_path", [] { return path_strings(current_registry()->search_path()); },
          "The plugin folders in force, searched in order.");
    m.def("default_plugin_path", [] { return path_strings(Registry::default_search_path()); },
          "The folder installed beside libmbd_core, then the folders of MBD_PLUGIN_PATH.");
    m.def("set_plugin_path", &set_plugin_path, py::arg("folders"),
          "Search these folders (None: the default path) for the models loaded from now on.");
    m.def("plugin_problems", [] { return current_registry()->problems(); },
          "Files of the plugin path that look like plugins but were skipped, with the reason.");
    m.attr("abi_version") = MBD_ABI_VERSION;          // element plugins (joint, force, body)
    m.attr("kit_abi_version") = MBD_KIT_ABI_VERSION;  // formulation, statics and inverse plugins
}

}  // namespace mbd::python
