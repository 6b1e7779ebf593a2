// mbd plugins: every plugin type found in the search path, without loading any library.
#include "commands.hpp"

#include <mbd/registry.hpp>

#include <algorithm>
#include <iomanip>
#include <iostream>

namespace mbd::cli {

void add_plugins_command(CLI::App& app, Commands& commands) {
    CLI::App* sub = app.add_subcommand(
        "plugins", "List every joint, force and formulation type found in the plugin folders, with its library, ABI and version");
    commands[sub] = [] {
        Registry registry;
        std::cout << "plugin search path:\n";
        for (const auto& dir : registry.search_path()) std::cout << "  " << dir.string() << '\n';
        std::cout << "host plugin ABI: " << MBD_ABI_VERSION << '\n';

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
            if (t.abi != MBD_ABI_VERSION) std::cout << "  (refused: built for ABI " << t.abi << ")";
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
