// libFuzzer target for the command line of `mbd`: the input is split at newlines into
// arguments and parsed by the same CLI::App as the mbd command (cli/command_line.cpp),
// with every option check (numbers, ranges, choices, files), without running a command.
// A parse either succeeds or throws a CLI11 error (printed by main() as a usage error);
// any other exception, a crash or undefined behaviour is a finding.
#include "commands.hpp"

#include <cstdint>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    std::vector<std::string> words{"mbd"};
    size_t start = 0;
    for (size_t end; (end = text.find('\n', start)) != std::string::npos; start = end + 1)
        words.push_back(text.substr(start, end - start));
    if (start < text.size()) words.push_back(text.substr(start));
    if (words.size() > 64) return 0;  // longer command lines add nothing but time

    std::vector<char*> argv;
    for (auto& w : words) argv.push_back(w.data());
    argv.push_back(nullptr);

    CLI::App app{"mbd", "mbd"};
    mbd::cli::Commands commands;
    mbd::cli::add_commands(app, commands);
    try {
        app.parse(static_cast<int>(words.size()), argv.data());
    } catch (const CLI::Error&) {
        // a usage error (or --help): main() prints it and exits 2
        return 0;
    }
    // a parse that succeeds selects exactly one command with an action
    int selected = 0;
    for (const CLI::App* sub : app.get_subcommands()) selected += commands.count(sub) ? 1 : 0;
    if (selected != 1) __builtin_trap();
    return 0;
}
