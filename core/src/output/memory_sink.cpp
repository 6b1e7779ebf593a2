// The in-memory sink (output_sink.hpp).
#include <mbd/output_sink.hpp>

#include <stdexcept>

namespace mbd {

void MemorySink::begin(const std::vector<std::string>& columns) {
    columns_ = columns;
    values_.clear();
    complete_ = false;
}

void MemorySink::row(const std::vector<double>& values) {
    if (values.size() != columns_.size())
        throw std::invalid_argument("output row has " + std::to_string(values.size()) + " values for " +
                                    std::to_string(columns_.size()) + " columns");
    values_.insert(values_.end(), values.begin(), values.end());
}

}  // namespace mbd
