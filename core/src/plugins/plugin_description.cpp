#include <mbd/plugin_description.hpp>

#include <boost/dll/shared_library.hpp>

#include <map>
#include <mutex>

namespace mbd {

const PluginDescription* plugin_description(const Registry& registry, const std::string& kind,
                                            const std::string& type) {
    const PluginType* found = nullptr;
    for (const PluginType& t : registry.types())
        if (t.kind == kind && t.type == type && t.abi == host_abi(kind)) {
            found = &t;
            break;
        }
    if (!found) return nullptr;
    // libraries opened for their descriptions stay open for the process's life (a description
    // is static data of its library); dlopen shares them with the registry's own handles
    static std::mutex mutex;
    static std::map<std::string, boost::dll::shared_library> opened;
    static std::map<std::string, const PluginDescription*> described;  // by library and symbol
    const std::lock_guard<std::mutex> lock(mutex);
    const std::string path = found->library.string();
    const std::string symbol = "mbd_keys" + std::to_string(MBD_KEYS_VERSION) + "__" + kind + "__" + type;
    if (auto known = described.find(path + ":" + symbol); known != described.end()) return known->second;
    auto it = opened.find(path);
    if (it == opened.end()) {
        boost::dll::shared_library library;
        boost::dll::fs::error_code error;
        library.load(found->library, boost::dll::load_mode::rtld_lazy | boost::dll::load_mode::rtld_local, error);
        if (error) return nullptr;
        it = opened.emplace(path, std::move(library)).first;
    }
    const PluginDescription* description =
        it->second.has(symbol) ? &it->second.get_alias<DescribePlugin>(symbol)() : nullptr;
    described[path + ":" + symbol] = description;
    return description;
}

std::vector<std::string> key_names(const PluginDescription& description) {
    std::vector<std::string> names;
    for (int k = 0; k < description.key_count(); ++k) names.emplace_back(description.keys[k].name);
    return names;
}

std::string key_default(const PluginKey& key) { return key.default_value ? key.default_value : "required"; }

}  // namespace mbd
