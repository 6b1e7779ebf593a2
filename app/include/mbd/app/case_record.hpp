// A finished case as bytes: what an MPI worker sends its master and what the results journal
// of a sweep (sweep_results.hpp) holds, in one encoding (native byte order: the journal is
// read back on the machine that wrote it, and MPI ranks of one job share it).
#pragma once

#include <mbd/app/study_case.hpp>

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace mbd {

using FinishedCase = std::pair<long, CaseResult>;

// Values appended as bytes.
class ByteWriter {
public:
    template <class T>
    void put(const T& value) {
        const std::size_t at = bytes.size();
        bytes.resize(at + sizeof(T));
        std::memcpy(bytes.data() + at, &value, sizeof(T));
    }
    void put(const std::string& text);
    void put(const std::vector<double>& values);
    std::vector<char> bytes;
};

// Values read back in the order written; std::runtime_error past the end.
class ByteReader {
public:
    ByteReader(const char* data, std::size_t size) : data_(data), size_(size) {}
    template <class T>
    T get() {
        T value;
        take(&value, sizeof(T));
        return value;
    }
    std::string text();
    std::vector<double> doubles();
    bool at_end() const { return at_ == size_; }

private:
    void take(void* into, std::size_t n);
    const char* data_;
    std::size_t size_;
    std::size_t at_ = 0;
};

std::vector<char> encode_case(long index, const CaseResult& result);
FinishedCase decode_case(const char* data, std::size_t size);

}  // namespace mbd
