// The HDF5 results file of a sweep (sweep_results.hpp), with the HDF5 C API, written from the
// journal in blocks of cases and read back in blocks of rows: memory bounded whatever the count.
//
// Layout (docs/sweep.md):
//   /                 attributes mbd_version, format ("mbd-sweep 1"), cases, finished, complete
//   /study            the study file's text (string)
//   /inputs/path, /inputs/content  every input file and its content's fingerprint
//   /design           cases x parameters, every planned case (attribute columns: the paths)
//   /table/case       finished cases, ascending case index (int64)
//   /table/parameters finished x parameters (attribute columns)
//   /table/metrics    finished x metrics (attribute columns); NaN for a failed case
//   /table/cpu_s, /table/status ("ok" | "failed"), /table/failure, /table/message
//   /series/case_K    rows x series columns of case K (attribute columns)
#include <mbd/app/sweep_results.hpp>

#include "hdf5_file.hpp"

#include <mbd/output_file.hpp>
#include <mbd/sdk/text.hpp>

#include <hdf5.h>

#include <cmath>
#include <cstdio>
#include <algorithm>
#include <limits>
#include <memory>
#include <stdexcept>

#ifndef MBD_VERSION
#define MBD_VERSION "unknown"
#endif

namespace mbd {

namespace fs = std::filesystem;

namespace {

using h5::check;
using h5::Handle;
using h5::quiet_hdf5;
using h5::read_columns;
using h5::read_doubles;
using h5::read_long_attribute;
using h5::read_rows;
using h5::rows_selection;
using h5::string_type;
using h5::write_long_attribute;
using h5::write_rows;
using h5::write_string_attribute;
using h5::write_strings;
using h5::write_strings_attribute;

constexpr const char* kFormat = "mbd-sweep 1";

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

// A scalar string dataset.
void write_text(hid_t owner, const char* name, const std::string& text) {
    Handle type(string_type(), H5Tclose, "make a string type");
    Handle space(H5Screate(H5S_SCALAR), H5Sclose, "make a dataspace");
    Handle set(H5Dcreate2(owner, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose,
               std::string("create /") + name);
    const char* pointer = text.c_str();
    check(H5Dwrite(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, &pointer), std::string("write /") + name);
}

// ---- reading

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

// A dataset of `rows` rows (x `columns` when columns > 0), with its column names.
hid_t create_table(hid_t owner, const char* name, hid_t type, hsize_t rows, hsize_t columns,
                   const std::vector<std::string>* names) {
    const hsize_t dims[2] = {rows, columns};
    Handle space(H5Screate_simple(columns == 0 ? 1 : 2, dims, nullptr), H5Sclose, "make a dataspace");
    const hid_t set = H5Dcreate2(owner, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    if (set < 0) throw std::runtime_error(std::string("HDF5: cannot create dataset ") + name);
    if (names) write_strings_attribute(set, "columns", *names);
    return set;
}

// The table of a results file being written, a block of finished cases at a time.
class TableWriter {
public:
    TableWriter(hid_t file, const JournalHeader& header, const CaseDesign& design) : header_(header), design_(design) {
        const auto n = static_cast<hsize_t>(header.cases);
        const hsize_t P = header.parameters.size(), M = header.metrics.size();
        Handle text(string_type(), H5Tclose, "make a string type");
        design_set_ = create_table(file, "design", H5T_IEEE_F64LE, n, P, &header.parameters);
        table_ = H5Gcreate2(file, "table", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
        if (table_ < 0) throw std::runtime_error("HDF5: cannot create /table");
        case_ = create_table(table_, "case", H5T_STD_I64LE, n, 0, nullptr);
        parameters_ = create_table(table_, "parameters", H5T_IEEE_F64LE, n, P, &header.parameters);
        metrics_ = create_table(table_, "metrics", H5T_IEEE_F64LE, n, M, &header.metrics);
        cpu_ = create_table(table_, "cpu_s", H5T_IEEE_F64LE, n, 0, nullptr);
        status_ = create_table(table_, "status", text, n, 0, nullptr);
        failure_ = create_table(table_, "failure", text, n, 0, nullptr);
        message_ = create_table(table_, "message", text, n, 0, nullptr);
        if (!header.series.empty()) {
            series_ = H5Gcreate2(file, "series", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
            if (series_ < 0) throw std::runtime_error("HDF5: cannot create /series");
        }
    }
    ~TableWriter() {
        for (hid_t set : {design_set_, case_, parameters_, metrics_, cpu_, status_, failure_, message_})
            if (set >= 0) H5Dclose(set);
        if (series_ >= 0) H5Gclose(series_);
        if (table_ >= 0) H5Gclose(table_);
    }
    TableWriter(const TableWriter&) = delete;
    TableWriter& operator=(const TableWriter&) = delete;

    void add(FinishedCase c) {
        if (c.first < 0 || c.first >= header_.cases) throw std::runtime_error("sweep: a journal record of no case");
        if (series_ >= 0 && c.second.ok)
            write_matrix(series_, ("case_" + std::to_string(c.first)).c_str(), c.second.series,
                         static_cast<hsize_t>(c.second.series_rows), header_.series.size(), &header_.series);
        c.second.series.clear();
        block_.push_back(std::move(c));
        if (block_.size() >= kBlock) write_block();
    }

    // The rest of the block; every case must have been given.
    void finish() { write_block(); }

private:
    static constexpr std::size_t kBlock = 8192;

    void write_block() {
        if (block_.empty()) return;
        std::sort(block_.begin(), block_.end(), [](const FinishedCase& a, const FinishedCase& b) { return a.first < b.first; });
        std::vector<std::pair<hsize_t, hsize_t>> runs;
        const std::size_t P = header_.parameters.size(), M = header_.metrics.size();
        std::vector<long long> cases;
        std::vector<double> values, metrics, cpu;
        std::vector<const char*> status, failure, message;
        for (const FinishedCase& c : block_) {
            const auto index = static_cast<hsize_t>(c.first);
            if (!runs.empty() && runs.back().first + runs.back().second == index) ++runs.back().second;
            else runs.emplace_back(index, 1);
            cases.push_back(c.first);
            const std::vector<double> v = design_.values(c.first);
            values.insert(values.end(), v.begin(), v.end());
            const CaseResult& r = c.second;
            if (r.ok && r.metrics.size() == M) metrics.insert(metrics.end(), r.metrics.begin(), r.metrics.end());
            else metrics.insert(metrics.end(), M, std::numeric_limits<double>::quiet_NaN());
            cpu.push_back(r.cpu_seconds);
            status.push_back(r.ok ? "ok" : "failed");
            failure.push_back(r.failure.c_str());
            message.push_back(r.message.c_str());
        }
        Handle text(string_type(), H5Tclose, "make a string type");
        write_rows(design_set_, H5T_NATIVE_DOUBLE, values.data(), runs, P, "/design");
        write_rows(case_, H5T_NATIVE_LLONG, cases.data(), runs, 0, "/table/case");
        write_rows(parameters_, H5T_NATIVE_DOUBLE, values.data(), runs, P, "/table/parameters");
        write_rows(metrics_, H5T_NATIVE_DOUBLE, metrics.data(), runs, M, "/table/metrics");
        write_rows(cpu_, H5T_NATIVE_DOUBLE, cpu.data(), runs, 0, "/table/cpu_s");
        write_rows(status_, text, status.data(), runs, 0, "/table/status");
        write_rows(failure_, text, failure.data(), runs, 0, "/table/failure");
        write_rows(message_, text, message.data(), runs, 0, "/table/message");
        block_.clear();
    }

    const JournalHeader& header_;
    const CaseDesign& design_;
    hid_t design_set_ = -1, table_ = -1, case_ = -1, parameters_ = -1, metrics_ = -1, cpu_ = -1, status_ = -1,
          failure_ = -1, message_ = -1, series_ = -1;
    std::vector<FinishedCase> block_;
};

std::vector<std::string> read_string_rows(hid_t owner, const char* name, hsize_t first, hsize_t count) {
    Handle set(H5Dopen2(owner, name, H5P_DEFAULT), H5Dclose, std::string("open dataset ") + name);
    Handle type(string_type(), H5Tclose, "make a string type");
    std::vector<char*> pointers(count, nullptr);
    std::vector<std::string> out;
    if (count == 0) return out;
    Handle memory(H5Screate_simple(1, &count, nullptr), H5Sclose, "make a dataspace");
    Handle file(rows_selection(set, {{first, count}}, 0), H5Sclose, "select rows");
    check(H5Dread(set, type, memory, file, H5P_DEFAULT, pointers.data()), name);
    for (char* p : pointers) out.emplace_back(p ? p : "");
    H5Dvlen_reclaim(type, memory, H5P_DEFAULT, pointers.data());
    return out;
}

}  // namespace

void write_results_h5(const fs::path& target, const fs::path& journal, const CaseDesign& design) {
    quiet_hdf5();
    JournalHeader header;
    std::unique_ptr<Handle> file;
    std::unique_ptr<TableWriter> table;
    long records = 0;
    auto open = [&] {
        file = std::make_unique<Handle>(H5Fcreate(target.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose,
                                        "create " + target.string());
        write_string_attribute(*file, "mbd_version", MBD_VERSION);
        write_string_attribute(*file, "format", kFormat);
        write_long_attribute(*file, "cases", header.cases);
        write_long_attribute(*file, "finished", header.cases);
        write_long_attribute(*file, "complete", 1);
        write_text(*file, "study", header.study_text);
        Handle inputs(H5Gcreate2(*file, "inputs", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, "create /inputs");
        std::vector<std::string> paths, contents;
        for (const InputFingerprint& f : header.inputs) paths.push_back(f.path), contents.push_back(f.content);
        write_strings(inputs, "path", paths);
        write_strings(inputs, "content", contents);
        table = std::make_unique<TableWriter>(*file, header, design);
    };
    read_journal(journal, header, [&](const char* data, std::size_t size) {
        if (!file) open();
        table->add(decode_case(data, size));
        ++records;
    });
    if (!file) open();
    if (records != header.cases)
        throw std::logic_error("sweep: the journal holds " + std::to_string(records) + " of " +
                               std::to_string(header.cases) + " cases at commit");
    table->finish();
    table.reset();
    check(H5Fflush(*file, H5F_SCOPE_GLOBAL), "flush " + target.string());
    file.reset();
    h5::sync_file(target);  // on disk before it takes the final name
}

ResultsShape results_h5_shape(const fs::path& path) {
    quiet_hdf5();
    ResultsShape shape;
    try {
        Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, "open the file");
        shape.cases = static_cast<long>(read_long_attribute(file, "finished"));
        Handle table(H5Gopen2(file, "table", H5P_DEFAULT), H5Gclose, "open /table");
        {
            Handle set(H5Dopen2(table, "parameters", H5P_DEFAULT), H5Dclose, "open /table/parameters");
            shape.parameters = read_columns(set);
        }
        Handle set(H5Dopen2(table, "metrics", H5P_DEFAULT), H5Dclose, "open /table/metrics");
        shape.metrics = read_columns(set);
    } catch (const std::runtime_error& e) {
        throw InputError(path.string(), std::string("is not a complete sweep results file (") + e.what() + ")");
    }
    return shape;
}

std::map<long, SweepRow> read_results_h5(const fs::path& path, long first, long count, bool with_series) {
    const ResultsShape shape = results_h5_shape(path);
    if (count < 0 || first + count > shape.cases) count = std::max(0L, shape.cases - first);
    const auto f = static_cast<hsize_t>(first), n = static_cast<hsize_t>(count);
    const std::size_t P = shape.parameters.size(), M = shape.metrics.size();
    std::map<long, SweepRow> rows;
    try {
        Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, "open the file");
        Handle table(H5Gopen2(file, "table", H5P_DEFAULT), H5Gclose, "open /table");
        const std::vector<double> cases = read_rows(table, "case", f, n, 0);
        const std::vector<double> values = read_rows(table, "parameters", f, n, P);
        const std::vector<double> metrics = read_rows(table, "metrics", f, n, M);
        const std::vector<double> cpu = read_rows(table, "cpu_s", f, n, 0);
        const std::vector<std::string> status = read_string_rows(table, "status", f, n);
        const std::vector<std::string> failure = read_string_rows(table, "failure", f, n);
        const std::vector<std::string> message = read_string_rows(table, "message", f, n);
        for (std::size_t r = 0; r < n; ++r) {
            SweepRow row;
            row.values.assign(values.begin() + r * P, values.begin() + (r + 1) * P);
            CaseResult& c = row.result;
            c.ok = status[r] == "ok";
            c.failure = failure[r];
            c.message = message[r];
            c.cpu_seconds = cpu[r];
            if (c.ok) c.metrics.assign(metrics.begin() + r * M, metrics.begin() + (r + 1) * M);
            const long index = static_cast<long>(cases[r]);
            if (with_series && c.ok && H5Lexists(file, "series", H5P_DEFAULT) > 0) {
                std::vector<hsize_t> dims;
                const std::string name = "series/case_" + std::to_string(index);
                c.series = read_doubles(file, name.c_str(), dims);
                c.series_rows = dims.empty() ? 0 : static_cast<long>(dims[0]);
            }
            rows.emplace(index, std::move(row));
        }
    } catch (const std::runtime_error& e) {
        if (dynamic_cast<const InputError*>(&e)) throw;
        throw InputError(path.string(), std::string("is not a complete sweep results file (") + e.what() + ")");
    }
    return rows;
}

void SweepResults::write_csv(const fs::path& csv) const {
    const ResultsShape shape = results_h5_shape(path_);
    std::string header = "case";
    for (const std::string& p : shape.parameters) header += "," + csv_field(p);
    for (const std::string& m : shape.metrics) header += "," + csv_field(m);
    header += ",cpu_s,status,failure,message\n";
    OutputFile file(csv, header);
    constexpr long kBlock = 8192;  // rows in memory at a time
    for (long first = 0; first < shape.cases; first += kBlock)
        for (const auto& [index, row] : read_results_h5(path_, first, kBlock, false)) {
            std::string line = std::to_string(index);
            for (double v : row.values) line += "," + g17(v);
            for (std::size_t k = 0; k < shape.metrics.size(); ++k)
                line += "," + (row.result.ok ? g17(row.result.metrics[k]) : "");
            line += "," + g17(row.result.cpu_seconds) + "," + (row.result.ok ? "ok" : "failed") + "," +
                    csv_field(row.result.failure) + "," + csv_field(row.result.message) + "\n";
            file.write_record(line);
        }
    file.commit();
}

}  // namespace mbd
