// The output contract (see output_file.hpp).
#include <mbd/output_file.hpp>

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <mutex>
#include <stdexcept>
#include <system_error>
#include <unistd.h>

namespace mbd {

namespace fs = std::filesystem;

namespace {

// Records are written in blocks of whole records: when this much is buffered, or
// when the last write is this old (so that NAME.partial shows a long run's progress).
constexpr std::size_t kFlushBytes = 1 << 16;
constexpr std::chrono::milliseconds kFlushInterval(250);

std::mutex g_notes_mutex;
std::vector<std::string> g_notes;

std::string quoted(const fs::path& p) { return "'" + p.string() + "'"; }

// The same file: fs::equivalent when both exist (links, `./`, `..`, hard links),
// else the same absolute path after resolving the links that do exist.
bool same_file(const fs::path& a, const fs::path& b) {
    std::error_code ec;
    if (fs::exists(a, ec) && fs::exists(b, ec)) {
        const bool equal = fs::equivalent(a, b, ec);
        if (!ec) return equal;
    }
    const fs::path ca = fs::weakly_canonical(fs::absolute(a, ec), ec);
    if (ec) return false;
    const fs::path cb = fs::weakly_canonical(fs::absolute(b, ec), ec);
    return !ec && ca == cb;
}

void write_all(int fd, const char* data, std::size_t size, const fs::path& path) {
    while (size > 0) {
        const ssize_t n = ::write(fd, data, size);
        if (n < 0) {
            if (errno == EINTR) continue;
            throw OutputError(path, std::strerror(errno));
        }
        data += n;
        size -= static_cast<std::size_t>(n);
    }
}

}  // namespace

void check_output_path(const fs::path& output, const std::vector<fs::path>& inputs, const std::string& option) {
    if (output.empty()) return;
    const fs::path partial = output.string() + ".partial";
    for (const fs::path& input : inputs) {
        if (input.empty()) continue;
        if (same_file(output, input))
            throw InputError(option, quoted(output) + " is the input file " + quoted(input) +
                                         " (the same file by another path or link); writing the result there would "
                                         "destroy the input: choose another output name");
        if (same_file(partial, input))
            throw InputError(option, quoted(output) + " would be written through " + quoted(partial) +
                                         ", which is the input file " + quoted(input) +
                                         ": choose another output name");
    }
    std::error_code ec;
    if (fs::is_directory(output, ec))
        throw InputError(option, quoted(output) + " is a folder; give a file name (e.g. " +
                                     quoted(output / "result.csv") + ")");
    const fs::path folder = output.parent_path().empty() ? fs::path(".") : output.parent_path();
    if (!fs::is_directory(folder, ec))
        throw InputError(option, "cannot write " + quoted(output) + ": the folder " + quoted(folder) +
                                     " does not exist; create it first");
}

OutputFile::OutputFile(fs::path path, std::string_view header)
    : path_(std::move(path)), partial_(path_.string() + ".partial"), buffer_(header),
      last_flush_(std::chrono::steady_clock::now()) {
    // a device or FIFO is no file to complete under its final name: it is written in place
    std::error_code ec;
    const fs::file_status status = fs::status(path_, ec);
    stream_ = !ec && fs::exists(status) && !fs::is_regular_file(status) && !fs::is_directory(status);
    if (stream_) partial_ = path_;
    else lock_ = std::make_unique<OutputLock>(path_, "", "an mbd run writing it");
    fd_ = ::open(partial_.c_str(), O_WRONLY | O_CREAT | (stream_ ? 0 : O_TRUNC) | O_CLOEXEC, 0666);
    if (fd_ < 0) throw OutputError(path_, std::string(std::strerror(errno)) + " (creating " + quoted(partial_) + ")");
}

OutputFile::~OutputFile() {
    if (finished_) return;
    try {
        abandon();
    } catch (...) {
        // a destructor must not throw; abandon() has already closed the file
    }
}

void OutputFile::write_record(std::string_view record) {
    if (finished_) throw std::logic_error("OutputFile: write after commit() or abandon() of " + quoted(path_));
    buffer_.append(record.data(), record.size());
    ++records_;
    ++buffered_records_;
    const auto now = std::chrono::steady_clock::now();
    if (buffer_.size() >= kFlushBytes || now - last_flush_ >= kFlushInterval) {
        flush_buffer();
        last_flush_ = now;
    }
}

void OutputFile::replace(std::string_view document, const std::string& contents) {
    if (finished_) throw std::logic_error("OutputFile: write after commit() or abandon() of " + quoted(path_));
    buffer_.clear();
    try {
        if (!stream_ && (::ftruncate(fd_, 0) != 0 || ::lseek(fd_, 0, SEEK_SET) < 0))
            throw OutputError(partial_, std::strerror(errno));
        write_all(fd_, document.data(), document.size(), partial_);
    } catch (const std::exception& e) {
        // no half document: nothing is kept
        if (!stream_ && ::ftruncate(fd_, 0) == 0) ::lseek(fd_, 0, SEEK_SET);
        records_ = 0;
        write_failure_ = e.what();
        throw;
    }
    ++records_;
    contents_ = contents;
}

void OutputFile::write_document_part(std::string_view bytes) {
    if (finished_) throw std::logic_error("OutputFile: write after commit() or abandon() of " + quoted(path_));
    document_ = true;
    buffer_.append(bytes.data(), bytes.size());
    if (buffer_.size() >= kFlushBytes) flush_buffer();
}

DocumentStream::DocumentStream(OutputFile& file) : std::ostream(nullptr), buffer_(file) {
    rdbuf(&buffer_);
    exceptions(std::ios::badbit);  // the OutputError of a failed write reaches the caller
}

std::streamsize DocumentStream::Buffer::xsputn(const char* data, std::streamsize size) {
    file_.write_document_part(std::string_view(data, static_cast<std::size_t>(size)));
    return size;
}

DocumentStream::Buffer::int_type DocumentStream::Buffer::overflow(int_type c) {
    if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
    const char byte = traits_type::to_char_type(c);
    file_.write_document_part(std::string_view(&byte, 1));
    return c;
}

void OutputFile::flush_buffer() {
    if (buffer_.empty()) return;
    const off_t complete = ::lseek(fd_, 0, SEEK_CUR);
    try {
        write_all(fd_, buffer_.data(), buffer_.size(), partial_);
    } catch (const std::exception& e) {
        // keep the file at its last whole record (a full disk may have taken part of a block)
        if (!stream_ && complete >= 0 && ::ftruncate(fd_, complete) == 0) ::lseek(fd_, complete, SEEK_SET);
        buffer_.clear();
        records_ -= buffered_records_;
        buffered_records_ = 0;
        write_failure_ = e.what();
        throw;
    }
    buffer_.clear();
    buffered_records_ = 0;
}

void OutputFile::close_descriptor() {
    if (fd_ < 0) return;
    const int fd = fd_;
    fd_ = -1;
    if (::close(fd) != 0 && errno != EINTR) throw OutputError(partial_, std::strerror(errno));
}

void OutputFile::commit() {
    if (finished_) return;
    finished_ = true;
    try {
        flush_buffer();
        close_descriptor();
    } catch (...) {
        close_descriptor();
        throw;
    }
    if (stream_) return;
    std::error_code ec;
    fs::rename(partial_, path_, ec);
    if (ec) throw OutputError(path_, ec.message() + " (renaming " + quoted(partial_) + ")");
}

void OutputFile::abandon(const std::string& what) {
    if (finished_) return;
    finished_ = true;
    std::string problem;
    try {
        if (write_failure_.empty() && !document_) flush_buffer();
    } catch (const std::exception& e) {
        problem = e.what();
    }
    try {
        close_descriptor();
    } catch (const std::exception& e) {
        if (problem.empty()) problem = e.what();
    }
    if (stream_) return;  // nothing to keep or remove: the device had the bytes
    std::error_code ec;
    if (records_ == 0 || document_) {
        fs::remove(partial_, ec);
        return;
    }
    // after a failed write the caller's description may count records that never arrived
    const std::string kept = !write_failure_.empty() ? "the " + std::to_string(records_) +
                                                           " records written before the write failed"
                             : !what.empty()         ? what
                             : !contents_.empty()    ? contents_
                                                     : "the " + std::to_string(records_) + " records written so far";
    std::lock_guard<std::mutex> lock(g_notes_mutex);
    g_notes.push_back(quoted(partial_) + " holds " + kept + "; " + quoted(path_) + " was not written" +
                      (problem.empty() ? "" : " (" + problem + ")"));
}

std::vector<std::string> take_kept_output_notes() {
    std::lock_guard<std::mutex> lock(g_notes_mutex);
    std::vector<std::string> notes;
    notes.swap(g_notes);
    return notes;
}

}  // namespace mbd
