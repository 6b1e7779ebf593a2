// A finished case as bytes (case_record.hpp).
#include <mbd/app/case_record.hpp>

namespace mbd {

void ByteWriter::put(const std::string& text) {
    put(static_cast<std::uint64_t>(text.size()));
    bytes.insert(bytes.end(), text.begin(), text.end());
}

void ByteWriter::put(const std::vector<double>& values) {
    put(static_cast<std::uint64_t>(values.size()));
    const auto* p = reinterpret_cast<const char*>(values.data());
    bytes.insert(bytes.end(), p, p + values.size() * sizeof(double));
}

void ByteReader::take(void* into, std::size_t n) {
    if (n > size_ - at_) throw std::runtime_error("sweep: a truncated case record");
    if (n == 0) return;  // (an empty vector's data() may be null, which memcpy must not be given)
    std::memcpy(into, data_ + at_, n);
    at_ += n;
}

std::string ByteReader::text() {
    const auto n = get<std::uint64_t>();
    if (n > size_ - at_) throw std::runtime_error("sweep: a truncated case record");
    std::string out(data_ + at_, static_cast<std::size_t>(n));
    at_ += static_cast<std::size_t>(n);
    return out;
}

std::vector<double> ByteReader::doubles() {
    const auto n = get<std::uint64_t>();
    if (n > (size_ - at_) / sizeof(double)) throw std::runtime_error("sweep: a truncated case record");
    std::vector<double> out(static_cast<std::size_t>(n));
    take(out.data(), out.size() * sizeof(double));
    return out;
}

std::vector<char> encode_case(long index, const CaseResult& r) {
    ByteWriter w;
    w.put(static_cast<std::int64_t>(index));
    w.put(static_cast<std::uint8_t>(r.ok ? 1 : 0));
    w.put(r.cpu_seconds);
    w.put(r.failure);
    w.put(r.message);
    w.put(r.metrics);
    w.put(static_cast<std::int64_t>(r.series_rows));
    w.put(r.series);
    return std::move(w.bytes);
}

FinishedCase decode_case(const char* data, std::size_t size) {
    ByteReader r(data, size);
    FinishedCase out;
    out.first = static_cast<long>(r.get<std::int64_t>());
    CaseResult& c = out.second;
    c.ok = r.get<std::uint8_t>() != 0;
    c.cpu_seconds = r.get<double>();
    c.failure = r.text();
    c.message = r.text();
    c.metrics = r.doubles();
    c.series_rows = static_cast<long>(r.get<std::int64_t>());
    c.series = r.doubles();
    return out;
}

}  // namespace mbd
