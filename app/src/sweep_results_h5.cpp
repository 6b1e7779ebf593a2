// The HDF5 results file of a sweep (sweep_results.hpp), with the HDF5 C API.
//
// Layout (docs/sweep.md):
//   /                 attributes mbd_version, format ("mbd-sweep 1"), cases, finished, complete
//   /study            the study file's text (string)
//   /design           cases x parameters, every planned case (attribute columns: the paths)
//   /table/case       finished cases, ascending case index (int64)
//   /table/parameters finished x parameters (attribute columns)
//   /table/metrics    finished x metrics (attribute columns); NaN for a failed case
//   /table/cpu_s, /table/status ("ok" | "failed"), /table/failure, /table/message
//   /series/case_K    rows x series columns of case K (attribute columns)
#include <mbd/app/sweep_results.hpp>

#include <mbd/output_file.hpp>
#include <mbd/sdk/text.hpp>

#include <hdf5.h>

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <stdexcept>

#ifndef MBD_VERSION
#define MBD_VERSION "unknown"
#endif

namespace mbd {

namespace fs = std::filesystem;

namespace {

constexpr const char* kFormat = "mbd-sweep 1";

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

void check(herr_t status, const std::string& what) {
    if (status < 0) throw std::runtime_error("HDF5: cannot " + what);
}

// HDF5 prints its error stack on stderr unless told not to; its failures become exceptions here.
void quiet_hdf5() {
    static const bool silenced = [] { return H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr) >= 0; }();
    (void)silenced;
}

hid_t string_type() {
    const hid_t t = H5Tcopy(H5T_C_S1);
    H5Tset_size(t, H5T_VARIABLE);
    H5Tset_cset(t, H5T_CSET_UTF8);
    return t;
}

void write_strings_attribute(hid_t owner, const char* name, const std::vector<std::string>& values) {
    Handle type(string_type(), H5Tclose, "make a string type");
    const hsize_t n = values.size();
    Handle space(H5Screate_simple(1, &n, nullptr), H5Sclose, "make a dataspace");
    Handle attribute(H5Acreate2(owner, name, type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
                     std::string("create attribute ") + name);
    std::vector<const char*> pointers;
    for (const std::string& v : values) pointers.push_back(v.c_str());
    if (n > 0) check(H5Awrite(attribute, type, pointers.data()), std::string("write attribute ") + name);
}

void write_string_attribute(hid_t owner, const char* name, const std::string& value) {
    Handle type(string_type(), H5Tclose, "make a string type");
    Handle space(H5Screate(H5S_SCALAR), H5Sclose, "make a dataspace");
    Handle attribute(H5Acreate2(owner, name, type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
                     std::string("create attribute ") + name);
    const char* pointer = value.c_str();
    check(H5Awrite(attribute, type, &pointer), std::string("write attribute ") + name);
}

void write_long_attribute(hid_t owner, const char* name, long long value) {
    Handle space(H5Screate(H5S_SCALAR), H5Sclose, "make a dataspace");
    Handle attribute(H5Acreate2(owner, name, H5T_STD_I64LE, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
                     std::string("create attribute ") + name);
    check(H5Awrite(attribute, H5T_NATIVE_LLONG, &value), std::string("write attribute ") + name);
}

// A rows x columns table of doubles (columns = 0: a vector), with its column names.
void write_matrix(hid_t owner, const char* name, const std::vector<double>& values, hsize_t rows, hsize_t columns,
                  const std::vector<std::string>* names) {
    const hsize_t dims[2] = {rows, columns};
    Handle space(H5Screate_simple(columns == 0 ? 1 : 2, dims, nullptr), H5Sclose, "make a dataspace");
    Handle set(H5Dcreate2(owner, name, H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose,
               std::string("create dataset ") + name);
    if (!values.empty()) check(H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), name);
    if (names) write_strings_attribute(set, "columns", *names);
}

void write_strings(hid_t owner, const char* name, const std::vector<std::string>& values) {
    Handle type(string_type(), H5Tclose, "make a string type");
    const hsize_t n = values.size();
    Handle space(H5Screate_simple(1, &n, nullptr), H5Sclose, "make a dataspace");
    Handle set(H5Dcreate2(owner, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose,
               std::string("create dataset ") + name);
    std::vector<const char*> pointers;
    for (const std::string& v : values) pointers.push_back(v.c_str());
    if (n > 0) check(H5Dwrite(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, pointers.data()), name);
}

// ---- reading (resume)

std::vector<hsize_t> dimensions(hid_t set) {
    Handle space(H5Dget_space(set), H5Sclose, "read a dataspace");
    const int rank = H5Sget_simple_extent_ndims(space);
    std::vector<hsize_t> dims(static_cast<std::size_t>(std::max(rank, 0)));
    if (rank > 0) H5Sget_simple_extent_dims(space, dims.data(), nullptr);
    return dims;
}

std::vector<double> read_doubles(hid_t owner, const char* name, std::vector<hsize_t>& dims) {
    Handle set(H5Dopen2(owner, name, H5P_DEFAULT), H5Dclose, std::string("open dataset ") + name);
    dims = dimensions(set);
    hsize_t total = 1;
    for (hsize_t d : dims) total *= d;
    std::vector<double> out(total);
    if (total > 0) check(H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()), name);
    return out;
}

std::vector<std::string> read_string_array(hid_t object, hid_t type_of, bool attribute, hsize_t n, const char* name) {
    Handle type(string_type(), H5Tclose, "make a string type");
    std::vector<char*> pointers(n, nullptr);
    if (n > 0)
        check(attribute ? H5Aread(object, type, pointers.data())
                        : H5Dread(object, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, pointers.data()),
              name);
    std::vector<std::string> out;
    for (char* p : pointers) out.emplace_back(p ? p : "");
    if (n > 0) {
        Handle space(attribute ? H5Aget_space(object) : H5Dget_space(object), H5Sclose, "read a dataspace");
        H5Dvlen_reclaim(type, space, H5P_DEFAULT, pointers.data());
    }
    (void)type_of;
    return out;
}

std::vector<std::string> read_strings(hid_t owner, const char* name) {
    Handle set(H5Dopen2(owner, name, H5P_DEFAULT), H5Dclose, std::string("open dataset ") + name);
    const std::vector<hsize_t> dims = dimensions(set);
    return read_string_array(set, 0, false, dims.empty() ? 1 : dims[0], name);
}

std::vector<std::string> read_columns(hid_t set) {
    Handle attribute(H5Aopen(set, "columns", H5P_DEFAULT), H5Aclose, "open attribute columns");
    Handle space(H5Aget_space(attribute), H5Sclose, "read a dataspace");
    hsize_t n = 0;
    H5Sget_simple_extent_dims(space, &n, nullptr);
    return read_string_array(attribute, 0, true, n, "columns");
}

std::string read_text(hid_t owner, const char* name) {
    Handle set(H5Dopen2(owner, name, H5P_DEFAULT), H5Dclose, std::string("open dataset ") + name);
    Handle type(string_type(), H5Tclose, "make a string type");
    char* pointer = nullptr;
    check(H5Dread(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, &pointer), name);
    std::string out = pointer ? pointer : "";
    Handle space(H5Dget_space(set), H5Sclose, "read a dataspace");
    H5Dvlen_reclaim(type, space, H5P_DEFAULT, &pointer);
    return out;
}

void write_all(int fd, const unsigned char* data, std::size_t size, const fs::path& path) {
    while (size > 0) {
        const ssize_t n = ::write(fd, data, size);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) throw OutputError(path, std::strerror(errno));
        data += n;
        size -= static_cast<std::size_t>(n);
    }
}

std::string csv_field(const std::string& text) {
    if (text.find_first_of(",\"\n") == std::string::npos) return text;
    std::string out = "\"";
    for (char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c == '\n' ? ' ' : c);
    return out + "\"";
}

std::string g17(double x) {
    char text[32];
    std::snprintf(text, sizeof text, "%.17g", x);
    return text;
}

}  // namespace

SweepResults::SweepResults(fs::path path, const Study& study, std::vector<std::vector<double>> design)
    : path_(std::move(path)), study_text_(study.text), design_(std::move(design)),
      last_write_(std::chrono::steady_clock::now()) {
    quiet_hdf5();
    for (const StudyParameter& p : study.parameters) parameters_.push_back(p.path);
    for (const StudyMetric& m : study.metrics) metrics_.push_back(m.name);
    series_ = study.series;
}

SweepResults SweepResults::create(const fs::path& path, const Study& study,
                                  const std::vector<std::vector<double>>& design) {
    SweepResults results(path, study, design);
    results.flush(true);
    return results;
}

SweepResults SweepResults::resume(const fs::path& path, const Study& study,
                                  const std::vector<std::vector<double>>& design) {
    SweepResults results(path, study, design);
    fs::path source = results.partial_path();
    std::error_code ec;
    if (!fs::exists(source, ec)) source = path;
    if (!fs::exists(source, ec))
        throw InputError("--resume", "there is no '" + results.partial_path().string() + "' nor '" + path.string() +
                                         "' to resume; run without --resume to start the study");
    const std::string where = source.string();
    try {
        Handle file(H5Fopen(source.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, "open the file");
        if (read_text(file, "study") != study.text)
            throw InputError(where, "holds the results of another study (its study file differs from " +
                                        study.file.string() + "); resume with the study that made it, or start anew");
        std::vector<hsize_t> dims;
        const std::vector<double> planned = read_doubles(file, "design", dims);
        std::vector<double> flat;
        for (const auto& row : design) flat.insert(flat.end(), row.begin(), row.end());
        if (planned != flat)
            throw InputError(where, "its design differs from the study's (another mbd version?); start anew");
        Handle table(H5Gopen2(file, "table", H5P_DEFAULT), H5Gclose, "open /table");
        std::vector<double> cases = read_doubles(table, "case", dims);
        const std::vector<double> values = read_doubles(table, "parameters", dims);
        const std::vector<double> metrics = read_doubles(table, "metrics", dims);
        const std::vector<double> cpu = read_doubles(table, "cpu_s", dims);
        const std::vector<std::string> status = read_strings(table, "status");
        const std::vector<std::string> failure = read_strings(table, "failure");
        const std::vector<std::string> message = read_strings(table, "message");
        const std::size_t P = results.parameters_.size(), M = results.metrics_.size(), S = results.series_.size();
        for (std::size_t r = 0; r < cases.size(); ++r) {
            SweepRow row;
            row.values.assign(values.begin() + r * P, values.begin() + (r + 1) * P);
            CaseResult& c = row.result;
            c.ok = status[r] == "ok";
            c.failure = failure[r];
            c.message = message[r];
            c.cpu_seconds = cpu[r];
            if (c.ok) c.metrics.assign(metrics.begin() + r * M, metrics.begin() + (r + 1) * M);
            const long index = static_cast<long>(cases[r]);
            if (c.ok && S > 0) {
                const std::string name = "series/case_" + std::to_string(index);
                c.series = read_doubles(file, name.c_str(), dims);
                c.series_rows = dims.empty() ? 0 : static_cast<long>(dims[0]);
            }
            results.rows_.emplace(index, std::move(row));
        }
    } catch (const std::runtime_error& e) {
        if (dynamic_cast<const InputError*>(&e)) throw;
        throw InputError(where, std::string("cannot be resumed, it is not a complete sweep results file (") +
                                    e.what() + ")");
    }
    return results;
}

long SweepResults::failed() const {
    long n = 0;
    for (const auto& [index, row] : rows_) n += row.result.ok ? 0 : 1;
    return n;
}

void SweepResults::add(long index, CaseResult result) {
    SweepRow row;
    row.values = design_.at(static_cast<std::size_t>(index));
    row.result = std::move(result);
    if (!rows_.emplace(index, std::move(row)).second)
        throw std::logic_error("sweep: case " + std::to_string(index) + " recorded twice");
    ++unwritten_;
}

std::vector<unsigned char> SweepResults::image() const {
    Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "make file access properties");
    check(H5Pset_fapl_core(fapl, 1 << 20, 0), "use the core driver");  // in memory, no backing file
    Handle file(H5Fcreate("mbd-sweep-image.h5", H5F_ACC_TRUNC, H5P_DEFAULT, fapl), H5Fclose, "create the file image");
    write_string_attribute(file, "mbd_version", MBD_VERSION);
    write_string_attribute(file, "format", kFormat);
    write_long_attribute(file, "cases", static_cast<long long>(design_.size()));
    write_long_attribute(file, "finished", static_cast<long long>(rows_.size()));
    write_long_attribute(file, "complete", rows_.size() == design_.size() ? 1 : 0);
    {
        Handle type(string_type(), H5Tclose, "make a string type");
        Handle space(H5Screate(H5S_SCALAR), H5Sclose, "make a dataspace");
        Handle set(H5Dcreate2(file, "study", type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose,
                   "create /study");
        const char* text = study_text_.c_str();
        check(H5Dwrite(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, &text), "write /study");
    }
    const std::size_t P = parameters_.size(), M = metrics_.size(), n = rows_.size();
    std::vector<double> planned;
    for (const auto& row : design_) planned.insert(planned.end(), row.begin(), row.end());
    write_matrix(file, "design", planned, design_.size(), P, &parameters_);

    std::vector<double> cases, values, metrics, cpu;
    std::vector<std::string> status, failure, message;
    for (const auto& [index, row] : rows_) {
        cases.push_back(static_cast<double>(index));
        values.insert(values.end(), row.values.begin(), row.values.end());
        if (row.result.ok) metrics.insert(metrics.end(), row.result.metrics.begin(), row.result.metrics.end());
        else metrics.insert(metrics.end(), M, std::numeric_limits<double>::quiet_NaN());
        cpu.push_back(row.result.cpu_seconds);
        status.push_back(row.result.ok ? "ok" : "failed");
        failure.push_back(row.result.failure);
        message.push_back(row.result.message);
    }
    Handle table(H5Gcreate2(file, "table", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, "create /table");
    {
        const hsize_t count = n;
        Handle space(H5Screate_simple(1, &count, nullptr), H5Sclose, "make a dataspace");
        Handle set(H5Dcreate2(table, "case", H5T_STD_I64LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose,
                   "create /table/case");
        if (n > 0) check(H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, cases.data()), "write case");
    }
    write_matrix(table, "parameters", values, n, P, &parameters_);
    write_matrix(table, "metrics", metrics, n, M, &metrics_);
    write_matrix(table, "cpu_s", cpu, n, 0, nullptr);
    write_strings(table, "status", status);
    write_strings(table, "failure", failure);
    write_strings(table, "message", message);
    if (!series_.empty()) {
        Handle series(H5Gcreate2(file, "series", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, "create /series");
        for (const auto& [index, row] : rows_)
            if (row.result.ok)
                write_matrix(series, ("case_" + std::to_string(index)).c_str(), row.result.series,
                             static_cast<hsize_t>(row.result.series_rows), series_.size(), &series_);
    }
    check(H5Fflush(file, H5F_SCOPE_GLOBAL), "flush the file image");
    const ssize_t size = H5Fget_file_image(file, nullptr, 0);
    if (size < 0) throw std::runtime_error("HDF5: cannot size the file image");
    std::vector<unsigned char> bytes(static_cast<std::size_t>(size));
    if (H5Fget_file_image(file, bytes.data(), bytes.size()) < 0) throw std::runtime_error("HDF5: cannot get the file image");
    return bytes;
}

// The image to `target` through TARGET.tmp, synced and renamed: `target` is never half written.
void SweepResults::write_image(const fs::path& target) const {
    const std::vector<unsigned char> bytes = image();
    const fs::path temporary = target.string() + ".tmp";
    const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    if (fd < 0) throw OutputError(path_, std::string(std::strerror(errno)) + " (creating '" + temporary.string() + "')");
    try {
        write_all(fd, bytes.data(), bytes.size(), temporary);
        if (::fsync(fd) != 0) throw OutputError(temporary, std::strerror(errno));
    } catch (...) {
        ::close(fd);
        ::unlink(temporary.c_str());
        throw;
    }
    ::close(fd);
    if (::rename(temporary.c_str(), target.c_str()) != 0) {
        const std::string why = std::strerror(errno);
        ::unlink(temporary.c_str());
        throw OutputError(target, why);
    }
}

void SweepResults::flush(bool force) {
    const auto now = std::chrono::steady_clock::now();
    const double since = std::chrono::duration<double>(now - last_write_).count();
    if (!force && (unwritten_ == 0 || since < std::max(interval_, 10.0 * last_write_seconds_))) return;
    write_image(partial_path());
    last_write_ = std::chrono::steady_clock::now();
    last_write_seconds_ = std::chrono::duration<double>(last_write_ - now).count();
    unwritten_ = 0;
}

void SweepResults::commit() {
    write_image(partial_path());
    if (::rename(partial_path().c_str(), path_.c_str()) != 0) throw OutputError(path_, std::strerror(errno));
    committed_ = true;
}

void SweepResults::write_csv(const fs::path& csv) const {
    std::string header = "case";
    for (const std::string& p : parameters_) header += "," + csv_field(p);
    for (const std::string& m : metrics_) header += "," + csv_field(m);
    header += ",cpu_s,status,failure,message\n";
    OutputFile file(csv, header);
    for (const auto& [index, row] : rows_) {
        std::string line = std::to_string(index);
        for (double v : row.values) line += "," + g17(v);
        for (std::size_t k = 0; k < metrics_.size(); ++k) line += "," + (row.result.ok ? g17(row.result.metrics[k]) : "");
        line += "," + g17(row.result.cpu_seconds) + "," + (row.result.ok ? "ok" : "failed") + "," +
                csv_field(row.result.failure) + "," + csv_field(row.result.message) + "\n";
        file.write_record(line);
    }
    file.commit();
}

}  // namespace mbd
