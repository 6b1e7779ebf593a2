// The journal of a running sweep, NAME.partial (sweep_results.hpp): a magic line, then
// records of [payload size: uint32][FNV-1a of the payload: uint64][payload], the first the
// header (encode_header), each other a finished case (encode_case). Native byte order: it is
// read back by the machine that wrote it.
#include <mbd/app/sweep_results.hpp>

#include <mbd/sdk/params.hpp>

#include <algorithm>
#include <cstring>
#include <fstream>

namespace mbd {

namespace {

constexpr char kMagic[] = "mbd-sweep-journal 1\n";
constexpr std::size_t kMagicSize = sizeof kMagic - 1;
constexpr std::size_t kFrame = sizeof(std::uint32_t) + sizeof(std::uint64_t);

std::uint64_t fnv1a(const char* data, std::size_t size) {
    std::uint64_t hash = 0xcbf29ce484222325ULL;
    for (std::size_t k = 0; k < size; ++k) {
        hash ^= static_cast<unsigned char>(data[k]);
        hash *= 0x100000001b3ULL;
    }
    return hash;
}

void put_names(ByteWriter& w, const std::vector<std::string>& names) {
    w.put(static_cast<std::uint64_t>(names.size()));
    for (const std::string& n : names) w.put(n);
}

std::vector<std::string> get_names(ByteReader& r) {
    std::vector<std::string> names(static_cast<std::size_t>(r.get<std::uint64_t>() & 0xffffff));
    for (std::string& n : names) n = r.text();
    return names;
}

}  // namespace

std::vector<char> encode_header(const JournalHeader& h) {
    ByteWriter w;
    w.put(h.study_text);
    w.put(static_cast<std::uint64_t>(h.inputs.size()));
    for (const InputFingerprint& f : h.inputs) {
        w.put(f.path);
        w.put(f.content);
    }
    put_names(w, h.parameters);
    put_names(w, h.metrics);
    put_names(w, h.series);
    w.put(static_cast<std::int64_t>(h.cases));
    w.put(h.design_signature);
    return std::move(w.bytes);
}

JournalHeader decode_header(const char* data, std::size_t size) {
    ByteReader r(data, size);
    JournalHeader h;
    h.study_text = r.text();
    h.inputs.resize(static_cast<std::size_t>(r.get<std::uint64_t>() & 0xffff));
    for (InputFingerprint& f : h.inputs) {
        f.path = r.text();
        f.content = r.text();
    }
    h.parameters = get_names(r);
    h.metrics = get_names(r);
    h.series = get_names(r);
    h.cases = static_cast<long>(r.get<std::int64_t>());
    h.design_signature = r.get<std::uint64_t>();
    return h;
}

std::string journal_record(const std::vector<char>& payload) {
    std::string out(kFrame + payload.size(), '\0');
    const auto size = static_cast<std::uint32_t>(payload.size());
    const std::uint64_t hash = fnv1a(payload.data(), payload.size());
    std::memcpy(out.data(), &size, sizeof size);
    std::memcpy(out.data() + sizeof size, &hash, sizeof hash);
    std::memcpy(out.data() + kFrame, payload.data(), payload.size());
    return out;
}

std::string journal_magic() { return std::string(kMagic, kMagicSize); }

std::size_t read_journal(const std::filesystem::path& file, JournalHeader& header,
                         const std::function<void(const char* data, std::size_t size)>& record) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw InputError(file.string(), "cannot be read");
    char magic[kMagicSize];
    if (!in.read(magic, kMagicSize) || std::memcmp(magic, kMagic, kMagicSize) != 0)
        throw InputError(file.string(), "is no sweep journal (mbd sweep's unfinished results); remove it to start anew");
    std::size_t whole = kMagicSize;
    std::vector<char> payload;
    bool first = true;
    for (;;) {
        std::uint32_t size = 0;
        std::uint64_t hash = 0;
        if (!in.read(reinterpret_cast<char*>(&size), sizeof size) || !in.read(reinterpret_cast<char*>(&hash), sizeof hash))
            break;
        payload.resize(size);
        if (!in.read(payload.data(), size) || fnv1a(payload.data(), size) != hash) break;  // cut by a kill
        if (first) header = decode_header(payload.data(), payload.size());
        else record(payload.data(), payload.size());
        first = false;
        whole += kFrame + size;
    }
    if (first) throw InputError(file.string(), "holds no complete header: the run that made it stopped at once; "
                                               "remove it to start anew");
    return whole;
}

std::uint64_t design_signature(const CaseDesign& design) {
    std::uint64_t hash = 0xcbf29ce484222325ULL;
    auto add = [&](long k) {
        const std::vector<double> v = design.values(k);
        hash ^= fnv1a(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(double));
        hash *= 0x100000001b3ULL;
    };
    for (long k = 0; k < std::min(design.cases(), 64L); ++k) add(k);
    if (design.cases() > 0) add(design.cases() - 1);
    return hash;
}

}  // namespace mbd
