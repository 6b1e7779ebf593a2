// Where `mbd bench` finds its peer programs (see bench.hpp): the folders the peers of this
// build are put in, found from the running executable's own location, so a plain
// `mbd bench` runs them without --peers.
#include <mbd/app/bench.hpp>

#include <filesystem>
#include <system_error>
#include <unistd.h>

namespace mbd {

namespace fs = std::filesystem;

std::vector<std::string> default_peer_dirs() {
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (ec) return {};
    const fs::path bin = exe.parent_path();
    // the build tree (bench/peers/CMakeLists.txt: bin/peers beside bin/mbd), then the install
    // tree (bin/mbd and libexec/mbd/peers; MBD_PEERS_FROM_BIN is the path between them)
    return {(bin / "peers").lexically_normal().string(), (bin / MBD_PEERS_FROM_BIN).lexically_normal().string()};
}

std::string peer_executable(const std::vector<std::string>& dirs, const std::string& engine, std::string& missing) {
    const std::string name = "mbd_peer_" + engine;
    std::string searched;
    for (const std::string& dir : dirs) {
        const fs::path exe = fs::path(dir) / name;
        std::error_code ec;
        if (fs::is_regular_file(exe, ec) && ::access(exe.c_str(), X_OK) == 0) return exe.string();
        searched += (searched.empty() ? "" : ", ") + dir;
    }
    missing = "peer " + engine + ": not installed (" +
              (dirs.empty() ? std::string("no peer folder known")
                            : "no " + name + " in " + searched + "; install lib" + engine +
                                  "-dev and rebuild bench/peers, or give --peers DIR") +
              "); skipped";
    return std::string();
}

}  // namespace mbd
