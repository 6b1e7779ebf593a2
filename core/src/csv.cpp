// Motion output in the CSV contract (see csv.hpp).
#include <mbd/csv.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace mbd {

std::vector<std::string> motion_columns(const Model& model) {
    std::vector<std::string> columns{"t"};
    const bool planar = model.dimension == Dimension::Planar;
    for (const Body& body : model.bodies) {
        const std::string& n = body.name;
        if (planar) {
            for (const char* s : {".x", ".y", ".angle"}) columns.push_back(n + s);
        } else {
            for (const char* s : {".x", ".y", ".z", ".e0", ".e1", ".e2", ".e3"}) columns.push_back(n + s);
        }
    }
    for (const Body& body : model.bodies) {
        const std::string& n = body.name;
        if (planar) {
            for (const char* s : {".vx", ".vy", ".omega"}) columns.push_back(n + s);
        } else {
            for (const char* s : {".vx", ".vy", ".vz", ".wx", ".wy", ".wz"}) columns.push_back(n + s);
        }
    }
    return columns;
}

std::vector<double> motion_values(const Model& model, const State& state) {
    if (state.q.size() != model.nq() || state.v.size() != model.nv())
        throw std::invalid_argument("motion_values: the state does not match the model (" +
                                    std::to_string(state.q.size()) + " coordinates, " +
                                    std::to_string(state.v.size()) + " velocities)");
    std::vector<double> values{state.t};
    const int nb = model.body_count();
    values.reserve(1 + nb * (coordinates_per_body(model.dimension) + velocities_per_body(model.dimension)));
    if (model.dimension == Dimension::Planar) {
        for (int b = 0; b < nb; ++b)
            for (int k = 0; k < 3; ++k) values.push_back(state.q[model.q_offset(b) + k]);
        for (int b = 0; b < nb; ++b)
            for (int k = 0; k < 3; ++k) values.push_back(state.v[model.v_offset(b) + k]);
    } else {
        for (int b = 0; b < nb; ++b)
            for (int k = 0; k < 7; ++k) values.push_back(state.q[model.q_offset(b) + k]);
        for (int b = 0; b < nb; ++b) {
            const int q0 = model.q_offset(b), v0 = model.v_offset(b);
            for (int k = 0; k < 3; ++k) values.push_back(state.v[v0 + k]);
            // angular velocity in world axes: w = A wbar
            const Vec4 p = state.q.segment<4>(q0 + 3);
            const Vec3 w = rotation_from_euler_parameters(p / p.norm()) * state.v.segment<3>(v0 + 3);
            for (int k = 0; k < 3; ++k) values.push_back(w[k]);
        }
    }
    return values;
}

CsvWriter::CsvWriter(const std::string& path, const std::vector<std::string>& columns)
    : path_(path), partial_(path + ".partial"), columns_(columns.size()) {
    out_.open(partial_, std::ios::out | std::ios::trunc);
    if (!out_) throw std::runtime_error("cannot write '" + partial_ + "' (does its folder exist?)");
    for (size_t k = 0; k < columns.size(); ++k) {
        if (k) out_ << ',';
        out_ << columns[k];
    }
    out_ << '\n';
}

CsvWriter::~CsvWriter() {
    if (!closed_) {
        // not closed: an error interrupted the run, so no result file appears
        out_.close();
        std::error_code ignored;
        std::filesystem::remove(partial_, ignored);
    }
}

void CsvWriter::row(const std::vector<double>& values) {
    if (closed_) throw std::logic_error("CsvWriter::row after close()");
    if (values.size() != columns_)
        throw std::invalid_argument("CSV row has " + std::to_string(values.size()) + " values for " +
                                    std::to_string(columns_) + " columns");
    for (size_t k = 0; k < values.size(); ++k)
        if (!std::isfinite(values[k]))
            throw std::runtime_error("refusing to write a non-finite value (" + std::to_string(values[k]) +
                                     ") in column " + std::to_string(k + 1) + " of '" + path_ + "'");
    char buffer[40];
    for (size_t k = 0; k < values.size(); ++k) {
        if (k) out_ << ',';
        std::snprintf(buffer, sizeof buffer, "%.17g", values[k]);
        out_ << buffer;
    }
    out_ << '\n';
    if (!out_) throw std::runtime_error("writing '" + partial_ + "' failed (disk full?)");
}

void CsvWriter::close() {
    if (closed_) return;
    out_.flush();
    const bool good = static_cast<bool>(out_);
    out_.close();
    closed_ = true;
    std::error_code error;
    if (!good) {
        std::filesystem::remove(partial_, error);
        throw std::runtime_error("writing '" + partial_ + "' failed (disk full?)");
    }
    std::filesystem::rename(partial_, path_, error);
    if (error) {
        std::error_code ignored;
        std::filesystem::remove(partial_, ignored);
        throw std::runtime_error("cannot rename '" + partial_ + "' to '" + path_ + "': " + error.message());
    }
}

}  // namespace mbd
