// The output interface of a run: the simulate driver (simulation.hpp) hands each output row to
// the sinks it is given and knows no format. A sink is told the run's columns, then gets every
// row (complete, finite, times increasing), then end() once the run is complete. A run that
// fails or is stopped never calls end(): a file sink is then destroyed unfinished and keeps what
// the output contract says (output_file.hpp: the complete rows in NAME.partial, nothing under NAME).
//
// The sinks: CSV (csv_sink.cpp, here), the in-memory table (MemorySink, here), HDF5 and the
// format table of `--output` (app/, output_formats.hpp), the animation (viewer/, animation_sink.hpp).
// A new format is one file defining its sink and an OutputFormat, plus one line in
// app/src/output_formats.cpp.
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace mbd {

class OutputSink {
public:
    virtual ~OutputSink() = default;
    // Before the first row; a file sink creates its file here (after the run's checks), and an
    // unusable file throws OutputError.
    virtual void begin(const std::vector<std::string>& columns) = 0;
    // One row, in the columns' order.
    virtual void row(const std::vector<double>& values) = 0;
    // The run is complete: the result takes its final form (a file its final name).
    virtual void end() = 0;
};

using OutputSinks = std::vector<OutputSink*>;

// A result file format of `--output`, chosen by the file's extension.
struct OutputFormat {
    std::string extension;    // with its dot: ".csv"
    std::string description;  // for messages: "CSV text"
    std::function<std::unique_ptr<OutputSink>(const std::filesystem::path&)> make;
};

// CSV in the contract of csv.hpp (17 significant digits: every double read back exactly).
OutputFormat csv_output_format();

// Every row in memory, row-major: what an embedding program or Python reads.
class MemorySink : public OutputSink {
public:
    void begin(const std::vector<std::string>& columns) override;
    void row(const std::vector<double>& values) override;
    void end() override { complete_ = true; }

    const std::vector<std::string>& columns() const { return columns_; }
    const std::vector<double>& values() const { return values_; }  // rows() x columns().size()
    std::size_t rows() const { return columns_.empty() ? 0 : values_.size() / columns_.size(); }
    double at(std::size_t row, std::size_t column) const { return values_[row * columns_.size() + column]; }
    bool complete() const { return complete_; }  // the run ended (end() was called)

private:
    std::vector<std::string> columns_;
    std::vector<double> values_;
    bool complete_ = false;
};

}  // namespace mbd
