// mbd plugins: every plugin type found in the search path, without loading any library.
#include "commands.hpp"

#include <mbd/plugin_description.hpp>
#include <mbd/registry.hpp>

#include <algorithm>
#include <iomanip>
#include <iostream>
#include <memory>

namespace mbd::cli {
namespace {

const char* bodies_text(int bodies) {
    return bodies == kEveryBody ? "every body" : bodies == kOneBody ? "one body (body: NAME)" : "two bodies (bodies: [a, b])";
}
const char* dimensions_text(int dimensions) {
    return dimensions == kPlanarOnly ? "planar" : dimensions == kSpatialOnly ? "spatial" : "planar and spatial";
}

// `mbd plugins --keys TYPE`: the keys a joint or force type describes, as a Markdown table.
int print_keys(const Registry& registry, const std::string& type) {
    int found = 0;
    for (const char* kind : {"joint", "force"}) {
        if (!registry.has(kind, type)) continue;
        ++found;
        const PluginDescription* d = plugin_description(registry, kind, type);
        if (!d) {
            std::cout << kind << " '" << type << "' describes no keys (a plugin built without MBD_"
                      << (std::string(kind) == "joint" ? "JOINT" : "FORCE") << "_KEYS)\n";
            continue;
        }
        std::cout << kind << " '" << type << "': " << d->summary << "; " << bodies_text(d->bodies) << "; "
                  << dimensions_text(d->dimensions) << "\n\n| key | meaning | default | example |\n|---|---|---|---|\n";
        for (int k = 0; k < d->key_count(); ++k) {
            const PluginKey& key = d->keys[k];
            std::cout << "| `" << key.name << "` | " << key.meaning << " | " << key_default(key) << " | `"
                      << (key.example ? key.example : "") << "`";
            if (key.example_spatial) std::cout << " (spatial `" << key.example_spatial << "`)";
            std::cout << " |\n";
        }
        if (d->key_count() == 0) std::cout << "| (none) | | | |\n";
    }
    if (found == 0) {
        std::cerr << "error: no joint or force type '" << type << "' in the plugin folders (mbd plugins lists them)\n";
        return 2;
    }
    return 0;
}

}  // namespace

void add_plugins_command(CLI::App& app, Commands& commands) {
    CLI::App* sub = app.add_subcommand(
        "plugins", "List every joint, force and formulation type found in the plugin folders, with its library, ABI and version");
    auto keys_of = std::make_shared<std::string>();
    sub->add_option("--keys", *keys_of,
                    "Print the keys a joint or force type describes (name, meaning, default, example) and exit");
    commands[sub] = [keys_of] {
        Registry registry;
        if (!keys_of->empty()) return print_keys(registry, *keys_of);
        std::cout << "plugin search path:\n";
        for (const auto& dir : registry.search_path()) std::cout << "  " << dir.string() << '\n';
        std::cout << "host plugin ABI: " << MBD_ABI_VERSION << " (joint, force, body)\n";
        std::cout << "host formulation kit ABI: " << MBD_KIT_ABI_VERSION << " (formulation, statics, inverse)\n";

        std::vector<PluginType> types = registry.types();
        std::stable_sort(types.begin(), types.end(), [](const PluginType& a, const PluginType& b) {
            return a.kind != b.kind ? a.kind < b.kind : a.type < b.type;
        });
        size_t kind_width = 4, type_width = 4;
        for (const auto& t : types) {
            kind_width = std::max(kind_width, t.kind.size());
            type_width = std::max(type_width, t.type.size());
        }
        std::cout << '\n' << std::left << std::setw(static_cast<int>(kind_width) + 2) << "kind"
                  << std::setw(static_cast<int>(type_width) + 2) << "type" << std::setw(6) << "ABI"
                  << std::setw(10) << "version" << "library\n";
        for (const auto& t : types) {
            std::cout << std::left << std::setw(static_cast<int>(kind_width) + 2) << t.kind
                      << std::setw(static_cast<int>(type_width) + 2) << t.type << std::setw(6) << t.abi
                      << std::setw(10) << t.version << t.library.string();
            if (t.abi != host_abi(t.kind)) std::cout << "  (refused: built for ABI " << t.abi << ")";
            std::cout << '\n';
        }
        if (types.empty()) std::cout << "(no plugin types found)\n";
        std::cout << '\n' << types.size() << " type" << (types.size() == 1 ? "" : "s") << " found\n";
        if (!registry.problems().empty()) {
            std::cout << "\nskipped files:\n";
            for (const auto& p : registry.problems()) std::cout << "  " << p << '\n';
        }
        return 0;
    };
}

}  // namespace mbd::cli
