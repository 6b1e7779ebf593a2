// The HDF5 files of mbd (the C API, Debian libhdf5-dev): the small mechanism the sweep's
// results file (sweep_results_h5.cpp) and the simulate sink (hdf5_sink.cpp) share. Failures
// of the library become std::runtime_error ("HDF5: cannot ..."); its own error printing is off.
#pragma once

#include <hdf5.h>

#include <filesystem>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace mbd::h5 {

// An HDF5 identifier closed by its own close function at the end of its scope.
class Handle {
public:
    Handle(hid_t id, herr_t (*close)(hid_t), const std::string& what) : id_(id), close_(close) {
        if (id_ < 0) throw std::runtime_error("HDF5: cannot " + what);
    }
    ~Handle() { close_(id_); }
    Handle(const Handle&) = delete;
    Handle& operator=(const Handle&) = delete;
    operator hid_t() const { return id_; }

private:
    hid_t id_;
    herr_t (*close_)(hid_t);
};

// Throws std::runtime_error "HDF5: cannot WHAT" for a negative status.
void check(herr_t status, const std::string& what);
// HDF5 prints its error stack on stderr unless told not to; its failures become exceptions here.
void quiet_hdf5();
// A variable-length UTF-8 string type (to be closed by the caller).
hid_t string_type();

void write_strings_attribute(hid_t owner, const char* name, const std::vector<std::string>& values);
void write_string_attribute(hid_t owner, const char* name, const std::string& value);
void write_long_attribute(hid_t owner, const char* name, long long value);
long long read_long_attribute(hid_t owner, const char* name);
// A 1-D dataset of strings (UTF-8).
void write_strings(hid_t owner, const char* name, const std::vector<std::string>& values);
// The dataset's "columns" attribute (a list of strings).
std::vector<std::string> read_columns(hid_t set);

// The dimensions of a dataset.
std::vector<hsize_t> dimensions(hid_t set);
// A whole dataset of doubles, and its dimensions.
std::vector<double> read_doubles(hid_t owner, const char* name, std::vector<hsize_t>& dims);
// The rows of `runs` ([first, first + count) each, ascending) of a dataset of `columns` columns
// (0: a vector) as one file selection (to be closed by the caller).
hid_t rows_selection(hid_t set, const std::vector<std::pair<hsize_t, hsize_t>>& runs, hsize_t columns);
// Writes `values` (rows x columns, row-major, in the order of the rows of `runs`) into `set`.
void write_rows(hid_t set, hid_t memory_type, const void* values, const std::vector<std::pair<hsize_t, hsize_t>>& runs,
                hsize_t columns, const char* name);
// Rows [first, first + count) of a table dataset as doubles (columns 0: a vector).
std::vector<double> read_rows(hid_t owner, const char* name, hsize_t first, hsize_t count, hsize_t columns);

// The file's bytes on disk (fsync) before it takes its final name; OutputError naming it.
void sync_file(const std::filesystem::path& file);

}  // namespace mbd::h5
