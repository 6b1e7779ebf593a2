// Fingerprints of a run's input files (input_fingerprint.hpp).
#include <mbd/app/input_fingerprint.hpp>

#include <mbd/sdk/params.hpp>

#include <cstdint>
#include <cstdio>
#include <fstream>

namespace mbd {

namespace {

// FNV-1a over 64 bits (Fowler, Noll, Vo): any change of the bytes changes it but for a chance
// of 2^-64; it guards against edits, not against an adversary.
std::string content_of(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw InputError(file.string(), "cannot read this input file to record its content");
    std::uint64_t hash = 0xcbf29ce484222325ULL;
    std::uint64_t bytes = 0;
    char block[1 << 16];
    while (in.read(block, sizeof block) || in.gcount() > 0) {
        const std::streamsize n = in.gcount();
        for (std::streamsize k = 0; k < n; ++k) {
            hash ^= static_cast<unsigned char>(block[k]);
            hash *= 0x100000001b3ULL;
        }
        bytes += static_cast<std::uint64_t>(n);
    }
    char text[64];
    std::snprintf(text, sizeof text, "fnv1a64:%016llx bytes:%llu", static_cast<unsigned long long>(hash),
                  static_cast<unsigned long long>(bytes));
    return text;
}

std::string listed(const std::vector<InputFingerprint>& inputs) {
    std::string out;
    for (const InputFingerprint& f : inputs) out += (out.empty() ? "'" : ", '") + f.path + "'";
    return out;
}

}  // namespace

std::vector<InputFingerprint> fingerprint_inputs(const std::vector<std::filesystem::path>& files) {
    std::vector<InputFingerprint> out;
    for (const std::filesystem::path& f : files) out.push_back({f.string(), content_of(f)});
    return out;
}

void check_same_inputs(const std::vector<InputFingerprint>& recorded, const std::vector<InputFingerprint>& now,
                       const std::string& where) {
    const std::string remedy = "; resume with the inputs that made its cases, or start anew without --resume";
    if (recorded.size() != now.size())
        throw InputError(where, "its cases were computed from " + std::to_string(recorded.size()) + " input files (" +
                                    listed(recorded) + "), the study now reads " + std::to_string(now.size()) + " (" +
                                    listed(now) + ")" + remedy);
    for (std::size_t k = 0; k < now.size(); ++k)
        if (recorded[k].content != now[k].content)
            throw InputError(where, "the input file '" + now[k].path + "' has changed since its cases were computed (" +
                                        "its content was " + recorded[k].content + ", it is now " + now[k].content +
                                        (recorded[k].path != now[k].path ? ", recorded as '" + recorded[k].path + "'" : "") +
                                        ")" + remedy);
}

}  // namespace mbd
