// `mbd simulate --output run.h5`: the rows of a run in an HDF5 file (output_sink.hpp), written
// as they arrive in bands of rows, each band one row of chunks, so memory stays bounded (about
// 4 MB of rows) whatever the run's length. Layout (docs/user-guide.md, "HDF5 results"):
//   /        attributes format ("mbd-simulation 1"), mbd_version, rows, complete (1)
//   /rows    float64, rows x columns (the CSV's rows), chunked, byte-shuffled and deflated:
//            the values are stored exactly
//   /columns the columns' names (strings, the CSV's header)
// The file is PATH.partial until the run ends, then synced and renamed to PATH; a failed or
// stopped run leaves no file (a part of it is no HDF5 file a reader can trust), and NAME.lock
// keeps a second run off the same output (output_lock.hpp).
#include <mbd/output_file.hpp>
#include <mbd/output_sink.hpp>

#include "hdf5_file.hpp"

#include <algorithm>
#include <memory>
#include <system_error>

#ifndef MBD_VERSION
#define MBD_VERSION "unknown"
#endif

namespace mbd {

namespace {

namespace fs = std::filesystem;

constexpr hsize_t kBandBytes = 4u << 20;    // rows held before they are written
constexpr hsize_t kChunkBytes = 64u << 10;  // one chunk: a band's rows x some columns

class Hdf5Sink : public OutputSink {
public:
    explicit Hdf5Sink(fs::path path) : path_(std::move(path)), partial_(path_.string() + ".partial") {}
    ~Hdf5Sink() override {
        if (ended_) return;
        set_.reset();  // not complete: no file is left (see above)
        file_.reset();
        std::error_code ec;
        if (file_made_) fs::remove(partial_, ec);
    }

    void begin(const std::vector<std::string>& columns) override {
        h5::quiet_hdf5();
        lock_ = std::make_unique<OutputLock>(path_, "--output", "an mbd run writing it");
        columns_ = std::max<hsize_t>(columns.size(), 1);
        band_ = std::clamp<hsize_t>(kBandBytes / (sizeof(double) * columns_), 1, 4096);
        try {
            file_ = std::make_unique<h5::Handle>(H5Fcreate(partial_.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT),
                                                 H5Fclose, "create " + partial_.string());
            file_made_ = true;
            h5::write_string_attribute(*file_, "format", "mbd-simulation 1");
            h5::write_string_attribute(*file_, "mbd_version", MBD_VERSION);
            const hsize_t dims[2] = {0, columns_}, max_dims[2] = {H5S_UNLIMITED, columns_};
            const hsize_t chunk[2] = {band_, std::clamp<hsize_t>(kChunkBytes / (sizeof(double) * band_), 1, columns_)};
            h5::Handle space(H5Screate_simple(2, dims, max_dims), H5Sclose, "make a dataspace");
            h5::Handle properties(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, "make dataset properties");
            h5::check(H5Pset_chunk(properties, 2, chunk), "set the chunks of /rows");
            h5::check(H5Pset_shuffle(properties), "shuffle /rows");  // byte planes: far better deflated
            h5::check(H5Pset_deflate(properties, 1), "deflate /rows");  // higher levels gain 1 %, at 2x the time
            set_ = std::make_unique<h5::Handle>(
                H5Dcreate2(*file_, "rows", H5T_IEEE_F64LE, space, H5P_DEFAULT, properties, H5P_DEFAULT), H5Dclose,
                "create /rows");
            h5::write_strings(*file_, "columns", columns);  // no attribute: 12,001 names pass its 64 kB
        } catch (const std::runtime_error& e) {
            throw OutputError(path_, e.what());
        }
        buffer_.reserve(band_ * columns_);
    }

    void row(const std::vector<double>& values) override {
        buffer_.insert(buffer_.end(), values.begin(), values.end());
        if (buffer_.size() < band_ * columns_) return;
        try {
            write_band();
        } catch (const std::runtime_error& e) {
            throw OutputError(path_, e.what());  // a full disk: bad output, named
        }
    }

    void end() override {
        try {
            write_band();
            h5::write_long_attribute(*file_, "rows", static_cast<long long>(rows_));
            h5::write_long_attribute(*file_, "complete", 1);
            set_.reset();
            h5::check(H5Fflush(*file_, H5F_SCOPE_GLOBAL), "flush " + partial_.string());
            file_.reset();
        } catch (const std::runtime_error& e) {
            if (dynamic_cast<const OutputError*>(&e)) throw;
            throw OutputError(path_, e.what());
        }
        h5::sync_file(partial_);
        std::error_code ec;
        fs::rename(partial_, path_, ec);
        if (ec) throw OutputError(path_, ec.message() + " (renaming " + partial_.string() + ")");
        ended_ = true;
        lock_.reset();
    }

private:
    // The buffered rows appended to /rows.
    void write_band() {
        const hsize_t n = buffer_.size() / columns_;
        if (n == 0) return;
        const hsize_t extent[2] = {rows_ + n, columns_};
        h5::check(H5Dset_extent(*set_, extent), "extend /rows");
        const hsize_t dims[2] = {n, columns_};
        h5::Handle memory(H5Screate_simple(2, dims, nullptr), H5Sclose, "make a dataspace");
        h5::Handle file(h5::rows_selection(*set_, {{rows_, n}}, columns_), H5Sclose, "select rows");
        h5::check(H5Dwrite(*set_, H5T_NATIVE_DOUBLE, memory, file, H5P_DEFAULT, buffer_.data()), "write /rows");
        rows_ += n;
        buffer_.clear();
    }

    fs::path path_, partial_;
    std::unique_ptr<OutputLock> lock_;
    std::unique_ptr<h5::Handle> file_, set_;
    hsize_t columns_ = 1, band_ = 1, rows_ = 0;
    std::vector<double> buffer_;  // at most band_ rows
    bool file_made_ = false, ended_ = false;
};

}  // namespace

OutputFormat hdf5_output_format() {
    return {".h5", "HDF5", [](const fs::path& path) { return std::make_unique<Hdf5Sink>(path); }};
}

}  // namespace mbd
