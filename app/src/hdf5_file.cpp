// The shared HDF5 mechanism (hdf5_file.hpp).
#include "hdf5_file.hpp"

#include <mbd/output_file.hpp>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace mbd::h5 {

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

static std::vector<std::string> read_string_array(hid_t object, hid_t type_of, bool attribute, hsize_t n, const char* name) {
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

std::vector<std::string> read_columns(hid_t set) {
    Handle attribute(H5Aopen(set, "columns", H5P_DEFAULT), H5Aclose, "open attribute columns");
    Handle space(H5Aget_space(attribute), H5Sclose, "read a dataspace");
    hsize_t n = 0;
    H5Sget_simple_extent_dims(space, &n, nullptr);
    return read_string_array(attribute, 0, true, n, "columns");
}


// The rows of `runs` ([first, first + count) each, ascending) of a dataset of `columns` columns
// (0: a vector) as one file selection.
hid_t rows_selection(hid_t set, const std::vector<std::pair<hsize_t, hsize_t>>& runs, hsize_t columns) {
    const hid_t space = H5Dget_space(set);
    if (space < 0) throw std::runtime_error("HDF5: cannot read a dataspace");
    H5Sselect_none(space);
    for (const auto& [first, count] : runs) {
        const hsize_t start[2] = {first, 0}, size[2] = {count, columns};
        if (H5Sselect_hyperslab(space, H5S_SELECT_OR, start, nullptr, size, nullptr) < 0) {
            H5Sclose(space);
            throw std::runtime_error("HDF5: cannot select rows");
        }
    }
    return space;
}

// Writes `values` (rows x columns, row-major, in the order of the rows of `runs`) into `set`.
void write_rows(hid_t set, hid_t memory_type, const void* values, const std::vector<std::pair<hsize_t, hsize_t>>& runs,
                hsize_t columns, const char* name) {
    hsize_t rows = 0;
    for (const auto& run : runs) rows += run.second;
    if (rows == 0) return;
    const hsize_t dims[2] = {rows, columns};
    Handle memory(H5Screate_simple(columns == 0 ? 1 : 2, dims, nullptr), H5Sclose, "make a dataspace");
    Handle file(rows_selection(set, runs, columns), H5Sclose, "select rows");
    check(H5Dwrite(set, memory_type, memory, file, H5P_DEFAULT, values), std::string("write ") + name);
}


// Rows [first, first + count) of a table dataset as doubles (columns 0: a vector).
std::vector<double> read_rows(hid_t owner, const char* name, hsize_t first, hsize_t count, hsize_t columns) {
    Handle set(H5Dopen2(owner, name, H5P_DEFAULT), H5Dclose, std::string("open dataset ") + name);
    std::vector<double> out(count * std::max<hsize_t>(columns, 1));
    if (count == 0 || out.empty()) return out;
    const hsize_t dims[2] = {count, columns};
    Handle memory(H5Screate_simple(columns == 0 ? 1 : 2, dims, nullptr), H5Sclose, "make a dataspace");
    Handle file(rows_selection(set, {{first, count}}, columns), H5Sclose, "select rows");
    check(H5Dread(set, H5T_NATIVE_DOUBLE, memory, file, H5P_DEFAULT, out.data()), name);
    return out;
}


long long read_long_attribute(hid_t owner, const char* name) {
    Handle attribute(H5Aopen(owner, name, H5P_DEFAULT), H5Aclose, std::string("open attribute ") + name);
    long long value = 0;
    check(H5Aread(attribute, H5T_NATIVE_LLONG, &value), std::string("read attribute ") + name);
    return value;
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

void sync_file(const std::filesystem::path& file) {
    const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0 || ::fsync(fd) != 0) {
        const std::string why = std::strerror(errno);
        if (fd >= 0) ::close(fd);
        throw OutputError(file, why);
    }
    ::close(fd);
}

}  // namespace mbd::h5
