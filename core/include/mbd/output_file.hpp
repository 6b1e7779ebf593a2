// The output contract shared by every command that writes a result file
// (simulate, kinematics, inverse, statics --output, bench --csv/--json,
// stability --markdown, ...):
//
//  - the result is written to NAME.partial and renamed to NAME by commit(), so
//    the final name appears only for a complete result (an existing NAME is
//    replaced only then);
//  - records (CSV rows) reach the file whole: they are buffered and written in
//    whole records, so NAME.partial always ends at a complete record;
//  - a run that fails or is interrupted before commit() leaves the records written
//    so far in NAME.partial (none written: no file), and the note saying so is
//    kept for the command's final message (take_kept_output_notes());
//  - a document written in parts (an animation export, DocumentStream) is no
//    record: a run stopped before commit() leaves no file at all;
//  - an output path that is one of the run's input files (the scene, a `base:`
//    file, a CSV read), also through a symbolic link, `./` or `..`, is refused by
//    check_output_path() before anything runs;
//  - a file that cannot be written (missing or unwritable folder, disk full)
//    throws OutputError naming the path;
//  - a regular file is locked for the writer's life (NAME.lock, output_lock.hpp): a second
//    run on the same output refuses at its start instead of overwriting the first one's.
#pragma once

#include <mbd/output_lock.hpp>
#include <mbd/sdk/params.hpp>

#include <chrono>
#include <filesystem>
#include <memory>
#include <ostream>
#include <streambuf>
#include <string>
#include <string_view>
#include <vector>

namespace mbd {

// A result file that cannot be written. It is bad input (an unusable output path)
// or a full disk: `mbd` exits with status 2.
class OutputError : public InputError {
public:
    OutputError(const std::filesystem::path& path, const std::string& message)
        : InputError("", "cannot write '" + path.string() + "': " + message) {}
};

// Refuses (InputError naming the option) an output path that is, or whose
// NAME.partial is, one of the input files, or that is a folder or lies in a
// folder that does not exist. `option` names it in the message ("--output").
void check_output_path(const std::filesystem::path& output, const std::vector<std::filesystem::path>& inputs,
                       const std::string& option);

class OutputFile {
public:
    // Creates (or truncates) PATH.partial and writes `header` (not a record: a file
    // with a header and no record is not kept); throws OutputError.
    explicit OutputFile(std::filesystem::path path, std::string_view header = {});
    // Not committed: the records written so far stay in PATH.partial (see above).
    ~OutputFile();
    OutputFile(const OutputFile&) = delete;
    OutputFile& operator=(const OutputFile&) = delete;

    // One complete record, its line end included.
    void write_record(std::string_view record);
    // The whole document so far (a report regenerated as results come in): PATH.partial
    // then holds exactly `document`; `contents` says what that is, for the note left if
    // the run stops here (e.g. "the matrix of the first 3 cases").
    void replace(std::string_view document, const std::string& contents = "");
    // Bytes of a document that is complete only at commit() (a large export written as it
    // is produced, see DocumentStream): if the run stops before commit(), PATH.partial is
    // removed, since part of such a document is no result.
    void write_document_part(std::string_view bytes);
    // Everything written; PATH.partial becomes PATH. Throws OutputError.
    void commit();
    // Stop here: keep the records in PATH.partial and note what it holds (`what`, e.g.
    // "the 120 rows up to t = 1.2") for the final message; with no record, remove it.
    void abandon(const std::string& what = "");

    const std::filesystem::path& path() const { return path_; }
    std::filesystem::path partial_path() const { return partial_; }
    long records() const { return records_; }

private:
    void flush_buffer();
    void close_descriptor();

    std::filesystem::path path_, partial_;
    std::unique_ptr<OutputLock> lock_;  // none on a device or FIFO: nothing is made beside it
    int fd_ = -1;
    std::string buffer_;  // whole records not yet written
    long records_ = 0;           // records given, on disk or buffered
    long buffered_records_ = 0;  // of which still in buffer_
    std::string contents_;       // what PATH.partial holds, from replace()
    std::string write_failure_;  // a failed write: PATH.partial holds only the records before it
    bool finished_ = false;
    bool document_ = false;  // written by write_document_part: nothing kept when abandoned
    bool stream_ = false;    // PATH is a device or FIFO (/dev/null, /dev/stdout): written in place
    std::chrono::steady_clock::time_point last_flush_;
};

// A std::ostream writing an OutputFile's document (write_document_part); a failed write
// throws the OutputError out of the stream operation.
class DocumentStream : public std::ostream {
public:
    explicit DocumentStream(OutputFile& file);

private:
    class Buffer : public std::streambuf {
    public:
        explicit Buffer(OutputFile& file) : file_(file) {}

    protected:
        std::streamsize xsputn(const char* data, std::streamsize size) override;
        int_type overflow(int_type c) override;

    private:
        OutputFile& file_;
    };
    Buffer buffer_;
};

// Notes of the files abandoned since the last call ("'out.csv.partial' holds the 120
// rows up to t = 1.2; 'out.csv' was not written"), for the command's final message.
std::vector<std::string> take_kept_output_notes();

}  // namespace mbd
