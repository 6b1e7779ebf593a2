// The results of a sweep (docs/sweep.md, "The results file"): one HDF5 file written by one
// process (the master), holding the study file, the mbd version, the design, the table of
// every finished case (parameters, metrics, CPU time, status, failure kind and message) and
// optional per-case time series.
//
// Crash safety: the file is built in memory (HDF5's core driver) and every flush writes a
// complete image to NAME.partial.tmp, syncs it and renames it over NAME.partial, so that
// NAME.partial is at every moment the complete file of some flush: a kill (SIGKILL included)
// loses at most the cases finished since the last flush, and `--resume` reads the rest. The
// finished study is renamed to NAME (the output contract of output_file.hpp).
#pragma once

#include <mbd/app/study.hpp>
#include <mbd/app/study_case.hpp>

#include <chrono>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace mbd {

struct SweepRow {
    std::vector<double> values;   // the parameters
    CaseResult result;
};

class SweepResults {
public:
    // A new results file (NAME.partial with the study and no case yet), written at once so
    // that an unusable output is refused before any case runs (OutputError).
    static SweepResults create(const std::filesystem::path& path, const Study& study,
                               const std::vector<std::vector<double>>& design);
    // The finished cases of an earlier run of the same study, from NAME.partial (or NAME, a
    // finished study); InputError when there is none or it holds another study.
    static SweepResults resume(const std::filesystem::path& path, const Study& study,
                               const std::vector<std::vector<double>>& design);

    bool done(long index) const { return rows_.count(index) > 0; }
    long finished() const { return static_cast<long>(rows_.size()); }
    long cases() const { return static_cast<long>(design_.size()); }
    long failed() const;
    void add(long index, CaseResult result);

    // Writes NAME.partial when `force` or when due: at least `interval` seconds since the last
    // write and ten times as long as the last write took (the writing stays below a tenth of the run).
    void flush(bool force = false);
    void set_flush_interval(double seconds) { interval_ = seconds; }
    // Every case finished: the last image, renamed to NAME.
    void commit();
    bool committed() const { return committed_; }
    const std::filesystem::path& path() const { return path_; }
    std::filesystem::path partial_path() const { return path_.string() + ".partial"; }

    // The table as CSV (case, parameters, metrics, cpu_s, status, failure, message; a failed
    // case's metrics empty), in the output contract of output_file.hpp.
    void write_csv(const std::filesystem::path& csv) const;

    // The rows in case order (tests, the CSV).
    const std::map<long, SweepRow>& rows() const { return rows_; }

private:
    SweepResults(std::filesystem::path path, const Study& study, std::vector<std::vector<double>> design);
    std::vector<unsigned char> image() const;
    void write_image(const std::filesystem::path& target) const;

    std::filesystem::path path_;
    std::string study_text_;
    std::vector<std::string> parameters_, metrics_, series_;
    std::vector<std::vector<double>> design_;
    std::map<long, SweepRow> rows_;
    std::chrono::steady_clock::time_point last_write_;
    double last_write_seconds_ = 0.0;
    double interval_ = 1.0;
    long unwritten_ = 0;
    bool committed_ = false;
};

}  // namespace mbd
