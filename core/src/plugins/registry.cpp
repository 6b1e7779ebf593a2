#include <mbd/registry.hpp>
#include <mbd/sdk/body.hpp>
#include <mbd/sdk/suggest.hpp>

#include <boost/dll/library_info.hpp>
#include <boost/dll/runtime_symbol_info.hpp>
#include <boost/dll/shared_library.hpp>

#include <algorithm>
#include <cstdlib>
#include <regex>
#include <set>
#include <sstream>

namespace mbd {

namespace fs = std::filesystem;

void rethrow_input_error(const InputError& e, const std::string& message) {
    if (dynamic_cast<const PluginError*>(&e)) throw PluginError(e.where(), message);
    throw InputError(e.where(), message);
}

// An opened plugin library. Every object a plugin creates keeps a reference to
// it, so the code of the object's virtual functions cannot be unloaded under it.
struct Registry::Library {
    boost::dll::shared_library handle;
};

namespace {

const std::regex& symbol_pattern() {
    static const std::regex pattern("^mbd_abi([0-9]+)__([a-z0-9_]+?)__([a-z0-9_]+)$");
    return pattern;
}

bool looks_like_library(const fs::path& p) {
    const std::string name = p.filename().string();
    return p.extension() == ".so" || name.find(".so.") != std::string::npos;
}

// The ABI a kind's plugins are built for, and what to rebuild them against: the SDK's for
// element plugins, the formulation kit's for formulations, statics and inverse solvers.
std::string abi_name(const std::string& kind) { return is_kit_kind(kind) ? "formulation kit ABI" : "plugin ABI"; }
std::string host_abi_name(const std::string& kind) { return is_kit_kind(kind) ? "kit ABI" : "ABI"; }
std::string rebuild_against(const std::string& kind) { return is_kit_kind(kind) ? "this formulation kit" : "this SDK"; }

std::string join(const std::vector<std::string>& items, const std::string& separator) {
    std::string out;
    for (size_t k = 0; k < items.size(); ++k) out += (k ? separator : "") + items[k];
    return out;
}

}  // namespace

std::vector<fs::path> Registry::default_search_path() {
    std::vector<fs::path> path;
    // lib/mbd/plugins beside the folder holding libmbd_core (build and install trees alike)
    // (normalised: a library found through an RPATH of $ORIGIN/../.. is named through it)
    const fs::path core = boost::dll::this_line_location();
    path.push_back((core.parent_path() / MBD_PLUGIN_SUBDIR).lexically_normal());
    if (const char* extra = std::getenv("MBD_PLUGIN_PATH")) {
        std::stringstream in(extra);
        std::string item;
        while (std::getline(in, item, ':'))
            if (!item.empty()) path.emplace_back(item);
    }
    return path;
}

Registry::Registry(std::vector<fs::path> search_path) : search_path_(std::move(search_path)) {
    std::set<std::string> seen;  // kind/type already provided by an earlier folder
    for (const fs::path& dir : search_path_) {
        std::error_code ec;
        if (!fs::is_directory(dir, ec)) continue;
        std::vector<fs::path> files;
        for (const auto& entry : fs::directory_iterator(dir, ec))
            if (entry.is_regular_file() && looks_like_library(entry.path())) files.push_back(entry.path());
        std::sort(files.begin(), files.end());
        for (const fs::path& file : files) {
            std::vector<std::string> symbols;
            try {
                boost::dll::library_info info(file);
                symbols = info.symbols("mbdplug");
            } catch (const std::exception& e) {
                problems_.push_back(file.string() + ": not a readable shared library (" + e.what() + ")");
                continue;
            }
            std::string version = "unknown";
            static const std::regex version_pattern("^mbd_version__([0-9]+)_([0-9]+)_([0-9]+)$");
            for (const std::string& symbol : symbols) {
                std::smatch m;
                if (std::regex_match(symbol, m, version_pattern))
                    version = m[1].str() + "." + m[2].str() + "." + m[3].str();
            }
            for (const std::string& symbol : symbols) {
                std::smatch m;
                if (!std::regex_match(symbol, m, symbol_pattern())) continue;
                PluginType t{m[2], m[3], std::stoi(m[1]), fs::absolute(file), version};
                const std::string key = t.kind + "/" + t.type;
                if (t.abi != host_abi(t.kind)) {
                    problems_.push_back(file.string() + ": " + t.kind + " type '" + t.type + "' was built for " +
                                        abi_name(t.kind) + " " + std::to_string(t.abi) + ", this mbd uses " +
                                        host_abi_name(t.kind) + " " + std::to_string(host_abi(t.kind)) +
                                        "; rebuild it against " + rebuild_against(t.kind));
                } else if (seen.count(key)) {
                    continue;  // shadowed by an earlier folder
                } else {
                    seen.insert(key);
                }
                types_.push_back(t);
            }
        }
    }
}

Registry::~Registry() = default;

std::vector<std::string> Registry::type_names(const std::string& kind) const {
    std::vector<std::string> names;
    for (const PluginType& t : types_)
        if (t.kind == kind && t.abi == host_abi(kind)) names.push_back(t.type);
    std::sort(names.begin(), names.end());
    names.erase(std::unique(names.begin(), names.end()), names.end());
    return names;
}

bool Registry::has(const std::string& kind, const std::string& type) const {
    for (const PluginType& t : types_)
        if (t.kind == kind && t.type == type && t.abi == host_abi(kind)) return true;
    return false;
}

const PluginType& Registry::find(const std::string& kind, const std::string& type, const std::string& owner,
                                 const std::string& where) const {
    const PluginType* wrong_abi = nullptr;
    for (const PluginType& t : types_) {
        if (t.kind != kind || t.type != type) continue;
        if (t.abi == host_abi(kind)) return t;
        wrong_abi = &t;
    }
    if (wrong_abi)
        throw PluginError(where, owner + ": " + kind + " type '" + type + "' is provided by " +
                                    wrong_abi->library.string() + ", built for " + abi_name(kind) + " " +
                                    std::to_string(wrong_abi->abi) + " but this mbd uses " + host_abi_name(kind) + " " +
                                    std::to_string(host_abi(kind)) + "; rebuild the plugin against " +
                                    rebuild_against(kind));
    std::vector<std::string> known = type_names(kind);
    const std::string best = nearest_name(type, known);
    std::string folders;
    for (const fs::path& p : search_path_) folders += (folders.empty() ? "" : ", ") + p.string();
    throw PluginError(where, owner + ": unknown " + kind + " type '" + type + "'; " +
                                (best.empty() ? std::string() : "did you mean '" + best + "'? ") + "known " + kind +
                                " types: " + (known.empty() ? std::string("(none)") : join(known, ", ")) +
                                " (plugin folders searched: " + folders +
                                "; add a folder with MBD_PLUGIN_PATH)");
}

std::shared_ptr<Registry::Library> Registry::open(const fs::path& library) {
    const std::string key = library.string();
    const std::lock_guard<std::mutex> lock(mutex_);
    auto it = opened_.find(key);
    if (it != opened_.end()) return it->second;
    auto lib = std::make_shared<Library>();
    lib->handle.load(library, boost::dll::load_mode::rtld_lazy | boost::dll::load_mode::rtld_local);
    opened_[key] = lib;
    open_order_.push_back(key);
    return lib;
}

template <class Product, class Spec>
std::shared_ptr<Product> Registry::create(const std::string& kind, const Spec& spec, const std::string& where) {
    using Factory = std::unique_ptr<Product>(const Spec&);
    const std::string owner = kind + " '" + spec.name + "'";
    const PluginType& t = find(kind, spec.type, owner, where);
    std::shared_ptr<Library> lib;
    try {
        lib = open(t.library);
    } catch (const std::exception& e) {
        throw PluginError(where, owner + ": cannot load plugin " + t.library.string() + ": " + e.what());
    }
    const std::string symbol = "mbd_abi" + std::to_string(host_abi(kind)) + "__" + kind + "__" + spec.type;
    auto& factory = lib->handle.get_alias<Factory>(symbol);
    // A plugin's exception names neither the scene nor the element: add both (an
    // InputError that already has a location, from the scene's keys, is complete).
    const std::string plugin = " (plugin " + t.library.string() + ")";
    std::unique_ptr<Product> made;
    try {
        made = factory(spec);
    } catch (const InputError& e) {
        if (!e.where().empty()) throw;
        throw InputError(where, owner + ": " + e.message() + plugin);
    } catch (const std::exception& e) {
        throw PluginError(where, owner + ": the " + kind + " type '" + spec.type + "' could not be created: " + e.what() +
                                    plugin);
    } catch (...) {
        throw PluginError(where, owner + ": the " + kind + " type '" + spec.type +
                                    "' could not be created (the plugin threw an unknown exception)" + plugin);
    }
    if (!made) throw PluginError(where, owner + ": plugin " + t.library.string() + " returned nothing");
    // the deleter runs the plugin's destructor, then lets go of the library
    std::shared_ptr<void> keep_alive = lib;
    return std::shared_ptr<Product>(made.release(), [keep_alive](const Product* p) { delete p; });
}

std::shared_ptr<const Joint> Registry::create_joint(const JointSpec& spec, const std::string& where) {
    return create<Joint>("joint", spec, where);
}

std::shared_ptr<const FlexibleBody> Registry::create_body(const BodySpec& spec, const std::string& where) {
    return create<FlexibleBody>("body", spec, where);
}

std::shared_ptr<const Force> Registry::create_force(const ForceSpec& spec, const std::string& where) {
    return create<Force>("force", spec, where);
}

std::shared_ptr<Formulation> Registry::create_formulation(const FormulationSpec& spec, const std::string& where) {
    return create<Formulation>("formulation", spec, where);
}

std::shared_ptr<StaticsSolver> Registry::create_statics(const StaticsSpec& spec, const std::string& where) {
    return create<StaticsSolver>("statics", spec, where);
}

std::shared_ptr<InverseSolver> Registry::create_inverse(const InverseSpec& spec, const std::string& where) {
    return create<InverseSolver>("inverse", spec, where);
}

std::vector<std::string> Registry::loaded_libraries() const {
    const std::lock_guard<std::mutex> lock(mutex_);
    return open_order_;
}

}  // namespace mbd
