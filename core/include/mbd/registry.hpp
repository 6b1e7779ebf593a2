// The plugin registry (Boost.DLL). It scans the plugin folders, reads the type
// names, kinds and ABI versions each library exports (from the ELF symbol
// table, without loading the library), and loads a library only when a scene
// asks for one of its types. Element plugins (joint, force, body) must carry the SDK's ABI
// (MBD_ABI_VERSION), formulation, statics and inverse plugins the kit's (MBD_KIT_ABI_VERSION,
// host_abi in kit plugin.hpp).
#pragma once

#include <mbd/kit/formulation.hpp>
#include <mbd/kit/inverse.hpp>
#include <mbd/kit/statics.hpp>
#include <mbd/sdk/plugin.hpp>

#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace mbd {

struct BodySpec;      // sdk/body.hpp
class FlexibleBody;

// A plugin that cannot serve a request: an unknown type, one built for another ABI, a
// library that does not load, a factory that fails or returns nothing. Bad input like any
// InputError (`mbd` exits with status 2); Python raises it as mbd.PluginError.
class PluginError : public InputError {
public:
    using InputError::InputError;
};

// Throws `e` again with `message` in place of its own, keeping its class (a PluginError
// stays one), for code that adds context to an error on its way out.
[[noreturn]] void rethrow_input_error(const InputError& e, const std::string& message);

struct PluginType {
    std::string kind;       // "joint", "force", "formulation", ...
    std::string type;       // e.g. "revolute"
    int abi = 0;            // the SDK's ABI for element plugins, the kit's for the others (host_abi)
    std::filesystem::path library;
    std::string version;    // the library's version ("0.1.0"), "unknown" if it does not say
};

class Registry {
public:
    // The folder installed beside libmbd_core (lib/mbd/plugins), then every
    // folder in MBD_PLUGIN_PATH (colon-separated). Earlier folders win.
    static std::vector<std::filesystem::path> default_search_path();

    explicit Registry(std::vector<std::filesystem::path> search_path = default_search_path());
    ~Registry();
    Registry(const Registry&) = delete;
    Registry& operator=(const Registry&) = delete;

    const std::vector<std::filesystem::path>& search_path() const { return search_path_; }
    // Every type found, of every ABI (types with the wrong ABI are listed but refused).
    const std::vector<PluginType>& types() const { return types_; }
    // Names of usable types of one kind, sorted.
    std::vector<std::string> type_names(const std::string& kind) const;
    bool has(const std::string& kind, const std::string& type) const;

    // Create an element; throws InputError naming the element and listing the
    // known types when the type is unknown, or explaining an ABI mismatch.
    std::shared_ptr<const Joint> create_joint(const JointSpec& spec, const std::string& where);
    std::shared_ptr<const Force> create_force(const ForceSpec& spec, const std::string& where);
    // Formulations are stateful (scratch space): each call gives a new instance.
    std::shared_ptr<Formulation> create_formulation(const FormulationSpec& spec, const std::string& where);
    // Statics and inverse-dynamics solvers (stateful): a new instance per call.
    std::shared_ptr<StaticsSolver> create_statics(const StaticsSpec& spec, const std::string& where);
    std::shared_ptr<InverseSolver> create_inverse(const InverseSpec& spec, const std::string& where);
    // Flexible bodies (sdk/body.hpp), kind "body".
    std::shared_ptr<const FlexibleBody> create_body(const BodySpec& spec, const std::string& where);

    // Libraries opened so far (absolute paths), in the order they were opened.
    std::vector<std::string> loaded_libraries() const;
    // Files in the search path that look like plugins but were skipped, with the reason.
    const std::vector<std::string>& problems() const { return problems_; }

private:
    struct Library;
    const PluginType& find(const std::string& kind, const std::string& type, const std::string& owner,
                           const std::string& where) const;
    std::shared_ptr<Library> open(const std::filesystem::path& library);
    template <class Product, class Spec>
    std::shared_ptr<Product> create(const std::string& kind, const Spec& spec, const std::string& where);

    std::vector<std::filesystem::path> search_path_;
    std::vector<PluginType> types_;
    std::vector<std::string> problems_;
    // Libraries are opened on first use; threads creating elements at once take turns.
    mutable std::mutex mutex_;
    std::map<std::string, std::shared_ptr<Library>> opened_;
    std::vector<std::string> open_order_;
};

}  // namespace mbd
