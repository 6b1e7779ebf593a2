// The results of a sweep (docs/sweep.md, "The results file"), written by one process (the
// master) in memory bounded whatever the number of cases:
//
//  - while the sweep runs, NAME.partial is a journal: a header (the study file's text, the
//    content of every input file, the columns) and one record per finished case, appended in
//    whole records with a checksum each and synced at every flush. A kill (SIGKILL included)
//    loses at most the cases finished since the last flush; a record cut by the kill is
//    dropped by --resume, which reads the rest, checks that the study and every input file
//    are the ones the cases were computed from, and appends the cases still to run;
//  - when every case is done, the HDF5 file is written from the journal in blocks (the study,
//    its inputs, the design, the table in case order, the per-case series) to NAME.partial.tmp,
//    synced and renamed to NAME (the output contract of output_file.hpp); the journal is removed.
//
// In memory: one bit per case (done or not), the journal's unwritten records (at most 1 MB)
// and one block of the table while the HDF5 file is written.
#pragma once

#include <mbd/app/case_record.hpp>
#include <mbd/app/input_fingerprint.hpp>
#include <mbd/app/study.hpp>
#include <mbd/app/study_case.hpp>
#include <mbd/app/study_design.hpp>

#include <chrono>
#include <cstdint>
#include <functional>
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
    // A new journal NAME.partial with the study and no case yet, written at once so that an
    // unusable output is refused before any case runs (OutputError).
    static SweepResults create(const std::filesystem::path& path, const Study& study, const CaseDesign& design,
                               const std::vector<InputFingerprint>& inputs);
    // The finished cases of an earlier run from NAME.partial; InputError when there is none,
    // when it holds another study, or when any input file's content has changed since.
    static SweepResults resume(const std::filesystem::path& path, const Study& study, const CaseDesign& design,
                               const std::vector<InputFingerprint>& inputs);
    SweepResults(SweepResults&& other) noexcept;
    ~SweepResults();
    SweepResults(const SweepResults&) = delete;
    SweepResults& operator=(const SweepResults&) = delete;
    SweepResults& operator=(SweepResults&&) = delete;

    bool done(long index) const { return done_[static_cast<std::size_t>(index)]; }
    const std::vector<bool>& done_cases() const { return done_; }
    long finished() const { return finished_; }
    long cases() const { return design_.cases(); }
    long failed() const { return failed_; }
    void add(long index, const CaseResult& result);

    // Appends the unwritten records and syncs NAME.partial when `force` or when due: at least
    // `interval` seconds since the last sync and ten times as long as the last sync took.
    void flush(bool force = false);
    void set_flush_interval(double seconds) { interval_ = seconds; }
    // Every case finished: the HDF5 file NAME from the journal, which is then removed.
    void commit();
    bool committed() const { return committed_; }
    const std::filesystem::path& path() const { return path_; }
    std::filesystem::path partial_path() const { return path_.string() + ".partial"; }

    // The table of the committed file NAME as CSV (case, parameters, metrics, cpu_s, status,
    // failure, message; a failed case's metrics empty), in case order, read in blocks, in the
    // output contract of output_file.hpp.
    void write_csv(const std::filesystem::path& csv) const;

private:
    SweepResults(std::filesystem::path path, const Study& study, const CaseDesign& design,
                 std::vector<InputFingerprint> inputs);
    void append(const std::vector<char>& payload);
    void write_buffer();

    std::filesystem::path path_;
    std::string study_text_;
    std::vector<std::string> parameters_, metrics_, series_;
    CaseDesign design_;
    std::vector<InputFingerprint> inputs_;
    std::vector<bool> done_;
    long finished_ = 0, failed_ = 0;
    int fd_ = -1;                 // NAME.partial, open for appending
    std::string buffer_;          // whole records not yet written
    std::chrono::steady_clock::time_point last_sync_;
    double last_sync_seconds_ = 0.0;
    double interval_ = 1.0;
    long unsynced_ = 0;
    bool committed_ = false;
};

// Every finished case of a sweep's output, from NAME.partial while it runs (a journal), else
// from the finished HDF5 file NAME, by case index. All in memory: for tests and small studies.
std::map<long, SweepRow> read_sweep_rows(const std::filesystem::path& output);

// ---- the two files (sweep_journal.cpp, sweep_results_h5.cpp)

// What the journal's header holds.
struct JournalHeader {
    std::string study_text;
    std::vector<InputFingerprint> inputs;
    std::vector<std::string> parameters, metrics, series;
    long cases = 0;
    std::uint64_t design_signature = 0;  // of the first and last cases' values: the same design
};

std::string journal_magic();  // the journal's first line
std::vector<char> encode_header(const JournalHeader& header);
JournalHeader decode_header(const char* data, std::size_t size);
// A journal record: payload size (uint32), FNV-1a of the payload (uint64), the payload.
std::string journal_record(const std::vector<char>& payload);
// Reads the journal at `file`: its header, then each whole record's payload given to `record`;
// returns the length of the whole records (a torn last record is not counted). InputError when
// the file is no sweep journal.
std::size_t read_journal(const std::filesystem::path& file, JournalHeader& header,
                         const std::function<void(const char* data, std::size_t size)>& record);
std::uint64_t design_signature(const CaseDesign& design);

// Writes the complete HDF5 file `target` from the journal `journal` (every case finished).
void write_results_h5(const std::filesystem::path& target, const std::filesystem::path& journal,
                      const CaseDesign& design);
// Rows [first, first + count) of the HDF5 file's table (count < 0: to the end), with their
// series when `with_series`.
std::map<long, SweepRow> read_results_h5(const std::filesystem::path& file, long first = 0, long count = -1,
                                         bool with_series = true);
// Cases in the HDF5 file `file` and its column names.
struct ResultsShape {
    long cases = 0;
    std::vector<std::string> parameters, metrics;
};
ResultsShape results_h5_shape(const std::filesystem::path& file);

}  // namespace mbd
