// Motion output in the CSV contract (see csv.hpp).
#include <mbd/csv.hpp>
#include <mbd/sdk/text.hpp>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace mbd {

namespace {
// A body whose mass matrix varies (a floating frame with modes, ffrf_body) has coordinates that are
// not its nodes' positions: they are written too. ANCF bodies' coordinates are their nodes'
// positions and slopes, which the node columns already give.
bool has_coordinate_columns(const FlexibleBodyInstance& f) { return !f.body->constant_mass(); }
}  // namespace

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
    // each flexible body's nodes (the material points at FlexibleBody::node_parameters): position, then velocity
    for (const FlexibleBodyInstance& f : model.flexible_bodies)
        for (int k = 0; k < f.body->node_count(); ++k) {
            const std::string n = f.name + ".node" + std::to_string(k);
            const std::vector<const char*> parts =
                planar ? std::vector<const char*>{".x", ".y", ".vx", ".vy"}
                       : std::vector<const char*>{".x", ".y", ".z", ".vx", ".vy", ".vz"};
            for (const char* s : parts) columns.push_back(n + s);
        }
    // a floating-frame body's own coordinates (its frame and modes), then their rates
    for (const FlexibleBodyInstance& f : model.flexible_bodies)
        if (has_coordinate_columns(f)) {
            for (int k = 0; k < f.size; ++k) columns.push_back(f.name + "." + f.body->coordinate_name(k));
            for (int k = 0; k < f.size; ++k) columns.push_back(f.name + "." + f.body->coordinate_name(k) + "_rate");
        }
    return columns;
}

namespace {

// The flexible bodies' node columns of motion_columns().
void append_flexible_nodes(const Model& model, const State& state, std::vector<double>& values) {
    const int dimensions = model.dimension == Dimension::Planar ? 2 : 3;
    MaterialPoint point;
    for (const FlexibleBodyInstance& f : model.flexible_bodies) {
        const Eigen::VectorXd q = state.q.segment(f.offset, f.size), v = state.v.segment(f.v_offset, f.size);
        for (int k = 0; k < f.body->node_count(); ++k) {
            const std::vector<double> xi = f.body->node_parameters(k);
            f.body->point(q, v, xi.data(), point);
            for (int c = 0; c < dimensions; ++c) values.push_back(point.r[c]);
            for (int c = 0; c < dimensions; ++c) values.push_back(point.rdot[c]);
        }
    }
    for (const FlexibleBodyInstance& f : model.flexible_bodies)
        if (has_coordinate_columns(f)) {
            for (int k = 0; k < f.size; ++k) values.push_back(state.q[f.offset + k]);
            for (int k = 0; k < f.size; ++k) values.push_back(state.v[f.v_offset + k]);
        }
}

}  // namespace

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
    append_flexible_nodes(model, state, values);
    return values;
}

State motion_state(const Model& model, const double* values) {
    State state;
    state.set_zero(model.nq(), model.nv());
    state.t = values[0];
    const int nb = model.body_count(), nc = coordinates_per_body(model.dimension), nw = velocities_per_body(model.dimension);
    const double* velocities = values + 1 + nb * nc;
    for (int b = 0; b < nb; ++b) {
        const int q0 = model.q_offset(b), v0 = model.v_offset(b);
        for (int k = 0; k < nc; ++k) state.q[q0 + k] = values[1 + b * nc + k];
        for (int k = 0; k < nw; ++k) state.v[v0 + k] = velocities[b * nw + k];
        if (model.dimension == Dimension::Spatial) {  // wbar = A^T w
            const Vec4 p = state.q.segment<4>(q0 + 3);
            state.v.segment<3>(v0 + 3) = rotation_from_euler_parameters(p / p.norm()).transpose() * state.v.segment<3>(v0 + 3);
        }
    }
    return state;
}

std::string CsvWriter::header(const std::vector<std::string>& columns) {
    std::string line;
    for (size_t k = 0; k < columns.size(); ++k) line += (k ? "," : "") + columns[k];
    return line + '\n';
}

CsvWriter::CsvWriter(const std::string& path, const std::vector<std::string>& columns)
    : file_(path, header(columns)), columns_(columns.size()), timed_(!columns.empty() && columns[0] == "t") {}

CsvWriter::~CsvWriter() {
    // not closed: the run failed or was interrupted; its complete rows stay in PATH.partial
    char last[40];
    std::snprintf(last, sizeof last, "%.9g", last_time_);
    file_.abandon("the " + std::to_string(rows()) + (rows() == 1 ? " row" : " rows") +
                  (timed_ ? std::string(" up to t = ") + last : std::string()) + " written before the stop");
}

void CsvWriter::row(const std::vector<double>& values) {
    if (values.size() != columns_)
        throw std::invalid_argument("CSV row has " + std::to_string(values.size()) + " values for " +
                                    std::to_string(columns_) + " columns");
    for (size_t k = 0; k < values.size(); ++k)
        if (!std::isfinite(values[k]))
            throw std::runtime_error("refusing to write a non-finite value (" + format_number(values[k]) +
                                     ") in column " + std::to_string(k + 1) + " of '" + file_.path().string() + "'");
    line_.clear();
    // std::to_chars writes what "%.17g" writes (both exactly rounded), without printf's parsing
    // and big-number arithmetic: the output of a 10,000-link chain cost more than its rk4 step
    char buffer[40];
    for (size_t k = 0; k < values.size(); ++k) {
        char* end = buffer;
        if (k) *end++ = ',';
        end = std::to_chars(end, buffer + sizeof buffer, values[k], std::chars_format::general, 17).ptr;
        line_.append(buffer, end);
    }
    line_ += '\n';
    file_.write_record(line_);
    if (timed_) last_time_ = values[0];
}

void CsvWriter::close() { file_.commit(); }

}  // namespace mbd
