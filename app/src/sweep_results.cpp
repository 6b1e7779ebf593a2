// The results of a sweep: the journal while it runs, the HDF5 file at the end (sweep_results.hpp).
#include <mbd/app/sweep_results.hpp>

#include <mbd/output_file.hpp>

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace mbd {

namespace fs = std::filesystem;

namespace {

// Unwritten records beyond this are written at once (the sync waits for the interval).
constexpr std::size_t kBufferBytes = 1 << 20;

std::string quoted(const fs::path& p) { return "'" + p.string() + "'"; }

void write_all(int fd, const char* data, std::size_t size, const fs::path& path) {
    while (size > 0) {
        const ssize_t n = ::write(fd, data, size);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) throw OutputError(path, std::strerror(errno));
        data += n;
        size -= static_cast<std::size_t>(n);
    }
}

JournalHeader header_of(const Study& study, const CaseDesign& design, const std::vector<InputFingerprint>& inputs) {
    JournalHeader h;
    h.study_text = study.text;
    h.inputs = inputs;
    for (const StudyParameter& p : study.parameters) h.parameters.push_back(p.path);
    for (const StudyMetric& m : study.metrics) h.metrics.push_back(m.name);
    h.series = study.series;
    h.cases = design.cases();
    h.design_signature = design_signature(design);
    return h;
}

}  // namespace

SweepResults::SweepResults(fs::path path, const Study& study, const CaseDesign& design,
                           std::vector<InputFingerprint> inputs)
    : path_(std::move(path)), study_text_(study.text), series_(study.series), design_(design),
      inputs_(std::move(inputs)), done_(static_cast<std::size_t>(design.cases()), false),
      last_sync_(std::chrono::steady_clock::now()) {
    for (const StudyParameter& p : study.parameters) parameters_.push_back(p.path);
    for (const StudyMetric& m : study.metrics) metrics_.push_back(m.name);
}

SweepResults::SweepResults(SweepResults&& o) noexcept
    : path_(std::move(o.path_)), study_text_(std::move(o.study_text_)), parameters_(std::move(o.parameters_)),
      metrics_(std::move(o.metrics_)), series_(std::move(o.series_)), design_(std::move(o.design_)),
      inputs_(std::move(o.inputs_)), done_(std::move(o.done_)), finished_(o.finished_), failed_(o.failed_),
      fd_(o.fd_), buffer_(std::move(o.buffer_)), last_sync_(o.last_sync_), last_sync_seconds_(o.last_sync_seconds_),
      interval_(o.interval_), unsynced_(o.unsynced_), committed_(o.committed_) {
    o.fd_ = -1;
}

SweepResults::~SweepResults() {
    if (fd_ < 0) return;
    try {
        write_buffer();  // an unfinished run keeps every case it recorded
    } catch (...) {
        // a destructor must not throw; the journal holds the whole records written before
    }
    ::close(fd_);
}

SweepResults SweepResults::create(const fs::path& path, const Study& study, const CaseDesign& design,
                                  const std::vector<InputFingerprint>& inputs) {
    SweepResults results(path, study, design, inputs);
    const fs::path partial = results.partial_path();
    results.fd_ = ::open(partial.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_APPEND | O_CLOEXEC, 0666);
    if (results.fd_ < 0)
        throw OutputError(path, std::string(std::strerror(errno)) + " (creating " + quoted(partial) + ")");
    results.buffer_ = journal_magic() + journal_record(encode_header(header_of(study, design, inputs)));
    results.flush(true);
    return results;
}

SweepResults SweepResults::resume(const fs::path& path, const Study& study, const CaseDesign& design,
                                  const std::vector<InputFingerprint>& inputs) {
    SweepResults results(path, study, design, inputs);
    const fs::path partial = results.partial_path();
    std::error_code ec;
    if (!fs::exists(partial, ec)) {
        if (fs::exists(path, ec))
            throw InputError("--resume", quoted(path) + " holds the finished study: there is nothing to resume; run "
                                         "without --resume and another output name to run it again");
        throw InputError("--resume", "there is no " + quoted(partial) + " to resume; run without --resume to start the study");
    }
    const std::string where = partial.string();
    JournalHeader header;
    bool checked = false;
    // the header is read before the first case: the study and its inputs are checked first
    auto check_header = [&] {
        if (checked) return;
        checked = true;
        if (header.study_text != study.text)
            throw InputError(where, "holds the results of another study (its study file differs from " +
                                        study.file.string() + "); resume with the study that made it, or start anew");
        check_same_inputs(header.inputs, inputs, where);
        const JournalHeader now = header_of(study, design, inputs);
        if (header.cases != now.cases || header.design_signature != now.design_signature ||
            header.parameters != now.parameters || header.metrics != now.metrics || header.series != now.series)
            throw InputError(where, "its design or columns differ from the study's (made by another mbd version?); "
                                    "start anew");
    };
    const std::size_t whole = read_journal(partial, header, [&](const char* data, std::size_t size) {
        check_header();
        const long index = static_cast<long>(ByteReader(data, size).get<std::int64_t>());
        if (index < 0 || index >= design.cases()) throw InputError(where, "holds a case of no case index: start anew");
        if (results.done_[static_cast<std::size_t>(index)]) return;
        results.done_[static_cast<std::size_t>(index)] = true;
        ++results.finished_;
        results.failed_ += decode_case(data, size).second.ok ? 0 : 1;
    });
    check_header();
    // append after the last whole record: a record cut by a kill is dropped
    results.fd_ = ::open(partial.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
    if (results.fd_ < 0 || ::truncate(partial.c_str(), static_cast<off_t>(whole)) != 0)
        throw OutputError(path, std::string(std::strerror(errno)) + " (reopening " + quoted(partial) + ")");
    return results;
}

void SweepResults::add(long index, const CaseResult& result) {
    if (done(index)) throw std::logic_error("sweep: case " + std::to_string(index) + " recorded twice");
    done_[static_cast<std::size_t>(index)] = true;
    ++finished_;
    failed_ += result.ok ? 0 : 1;
    buffer_ += journal_record(encode_case(index, result));
    ++unsynced_;
    if (buffer_.size() >= kBufferBytes) write_buffer();
}

void SweepResults::write_buffer() {
    if (buffer_.empty()) return;
    write_all(fd_, buffer_.data(), buffer_.size(), partial_path());
    buffer_.clear();
}

void SweepResults::flush(bool force) {
    const auto now = std::chrono::steady_clock::now();
    const double since = std::chrono::duration<double>(now - last_sync_).count();
    if (!force && (unsynced_ == 0 || since < std::max(interval_, 10.0 * last_sync_seconds_))) return;
    write_buffer();
    if (::fsync(fd_) != 0) throw OutputError(partial_path(), std::strerror(errno));
    last_sync_ = std::chrono::steady_clock::now();
    last_sync_seconds_ = std::chrono::duration<double>(last_sync_ - now).count();
    unsynced_ = 0;
}

void SweepResults::commit() {
    if (finished_ != cases()) throw std::logic_error("sweep: commit with cases still to run");
    flush(true);
    const fs::path temporary = partial_path().string() + ".tmp";
    try {
        write_results_h5(temporary, partial_path(), design_);
    } catch (...) {
        std::error_code ec;
        fs::remove(temporary, ec);
        throw;
    }
    if (::rename(temporary.c_str(), path_.c_str()) != 0) {
        const std::string why = std::strerror(errno);
        ::unlink(temporary.c_str());
        throw OutputError(path_, why + " (renaming " + quoted(temporary) + ")");
    }
    ::close(fd_);
    fd_ = -1;
    ::unlink(partial_path().c_str());  // the journal's cases are all in NAME now
    committed_ = true;
}

std::map<long, SweepRow> read_sweep_rows(const fs::path& output) {
    const fs::path partial = output.string() + ".partial";
    std::error_code ec;
    if (!fs::exists(partial, ec)) return read_results_h5(output);
    // the parameters of each case are not in the journal: they are the study's, by index
    std::map<long, SweepRow> rows;
    JournalHeader header;
    read_journal(partial, header, [&](const char* data, std::size_t size) {
        FinishedCase c = decode_case(data, size);
        rows[c.first].result = std::move(c.second);
    });
    return rows;
}

}  // namespace mbd
