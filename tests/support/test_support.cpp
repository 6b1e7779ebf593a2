#include "support/test_support.hpp"

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

namespace mbd::test {

std::filesystem::path source_dir() { return MBD_SOURCE_DIR; }
std::filesystem::path build_plugin_dir() { return std::filesystem::path(MBD_BUILD_DIR) / "lib/mbd/plugins"; }
std::filesystem::path scene_path(const std::string& relative) { return source_dir() / "scenes" / relative; }

Registry& shared_registry() {
    static Registry registry({build_plugin_dir()});
    return registry;
}

namespace {
std::string slurp(const std::filesystem::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}
}  // namespace

CommandResult run_command(const std::string& command) {
    const auto dir = std::filesystem::temp_directory_path();
    const std::string tag = std::to_string(::getpid()) + "_" + std::to_string(std::rand());
    const auto out = dir / ("mbd_test_out_" + tag);
    const auto err = dir / ("mbd_test_err_" + tag);
    const std::string full = command + " >" + out.string() + " 2>" + err.string() + " </dev/null";
    const int status = std::system(full.c_str());
    CommandResult r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = slurp(out);
    r.err = slurp(err);
    std::filesystem::remove(out);
    std::filesystem::remove(err);
    return r;
}

CommandResult run_mbd(const std::string& arguments) {
    return run_command(std::string("env -u MBD_PLUGIN_PATH ") + MBD_EXECUTABLE + " " + arguments);
}

}  // namespace mbd::test
