// The CSV sink (output_sink.hpp): the rows in the CSV contract of csv.hpp, through CsvWriter
// and so the output contract of output_file.hpp.
#include <mbd/csv.hpp>
#include <mbd/output_sink.hpp>

#include <optional>

namespace mbd {

namespace {

class CsvSink : public OutputSink {
public:
    explicit CsvSink(std::filesystem::path path) : path_(std::move(path)) {}
    void begin(const std::vector<std::string>& columns) override { writer_.emplace(path_.string(), columns); }
    void row(const std::vector<double>& values) override { writer_->row(values); }
    void end() override { writer_->close(); }

private:
    std::filesystem::path path_;
    std::optional<CsvWriter> writer_;  // made at begin(): no file for a run refused before it starts
};

}  // namespace

OutputFormat csv_output_format() {
    return {".csv", "CSV text", [](const std::filesystem::path& path) { return std::make_unique<CsvSink>(path); }};
}

}  // namespace mbd
