// The content of a run's input files, recorded with its results so that `mbd sweep --resume`
// can tell that every input (the study file, its scene, the scene's `base:` files) is the one
// the finished cases were computed from: a changed file is refused by name, never mixed in.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace mbd {

struct InputFingerprint {
    std::string path;     // as the run named it (for messages)
    std::string content;  // "fnv1a64:HEX16 bytes:N", a 64-bit FNV-1a hash of the bytes and their count
};

// The fingerprint of each file; InputError naming a file that cannot be read.
std::vector<InputFingerprint> fingerprint_inputs(const std::vector<std::filesystem::path>& files);

// Refuses (InputError at `where`, the results file) inputs that differ from those recorded:
// names the first changed file, or says the list of files changed (another base scene).
void check_same_inputs(const std::vector<InputFingerprint>& recorded, const std::vector<InputFingerprint>& now,
                       const std::string& where);

}  // namespace mbd
