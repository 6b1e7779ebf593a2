// Reading a result CSV back (the writer is core/src/output/csv.cpp) and finding each body's pose.
#include <mbd/viewer/motion_table.hpp>

#include <mbd/csv.hpp>

#include <algorithm>
#include <charconv>
#include <cstring>
#include <thread>
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>
#include <cmath>
#include <limits>
#include <fstream>
#include <map>
#include <sstream>

namespace mbd::viewer {
namespace {

std::string quote(const std::string& s) { return "'" + s + "'"; }

std::vector<std::string> split_header(const std::string& line) {
    std::vector<std::string> out;
    std::string item;
    std::stringstream s(line);
    while (std::getline(s, item, ',')) {
        while (!item.empty() && (item.back() == '\r' || item.back() == ' ')) item.pop_back();
        while (!item.empty() && item.front() == ' ') item.erase(item.begin());
        out.push_back(item);
    }
    return out;
}

// The file's bytes, mapped read-only: a result of several hundred MB is parsed in place,
// without a copy.
class MappedFile {
public:
    explicit MappedFile(const std::filesystem::path& file) {
        fd_ = ::open(file.c_str(), O_RDONLY);
        struct stat st {};
        if (fd_ < 0 || ::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode)) {
            if (fd_ >= 0) ::close(fd_);
            throw InputError(file.string(), "cannot open the result CSV; check the path");
        }
        size_ = static_cast<size_t>(st.st_size);
        if (size_ > 0) {
            void* m = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd_, 0);
            if (m == MAP_FAILED) {
                ::close(fd_);
                throw InputError(file.string(), "cannot read the result CSV");
            }
            data_ = static_cast<const char*>(m);
            ::madvise(m, size_, MADV_SEQUENTIAL);
        }
    }
    ~MappedFile() {
        if (data_) ::munmap(const_cast<char*>(data_), size_);
        ::close(fd_);
    }
    MappedFile(const MappedFile&) = delete;
    MappedFile& operator=(const MappedFile&) = delete;
    const char* data() const { return data_ ? data_ : ""; }
    size_t size() const { return size_; }

private:
    int fd_ = -1;
    const char* data_ = nullptr;
    size_t size_ = 0;
};

}  // namespace

namespace {

// One stretch of the file's rows, parsed by one thread into its place in the table.
struct RowBlock {
    const char* begin = nullptr;
    const char* end = nullptr;
    size_t first_line = 0;  // the file line of `begin`
    size_t first_row = 0;   // the table row of its first non-blank line
    size_t rows = 0;        // non-blank lines
    size_t lines = 0;
    size_t parsed = 0;      // rows parsed before the first error
    size_t first_data_line = 0;
    // the block's first error (none when line == 0): its file line and message
    size_t error_line = 0;
    std::string error;
};

void count_rows(RowBlock& block) {
    for (const char* p = block.begin; p < block.end;) {
        const char* eol = static_cast<const char*>(std::memchr(p, '\n', static_cast<size_t>(block.end - p)));
        if (!eol) eol = block.end;
        const char* row_end = eol > p && eol[-1] == '\r' ? eol - 1 : eol;
        ++block.lines;
        if (row_end > p) ++block.rows;
        p = eol < block.end ? eol + 1 : block.end;
    }
}

// Parses the block's rows into table.values; stops at the first malformed row. Times are
// checked to increase within the block (across blocks by the caller).
void parse_rows(RowBlock& block, const std::vector<std::string>& columns, double* out) {
    const size_t n = columns.size();
    size_t line = block.first_line;
    double previous_time = 0.0;
    size_t& parsed = block.parsed;
    auto fail = [&](std::string message) {
        block.error_line = line;
        block.error = std::move(message);
    };
    for (const char* p = block.begin; p < block.end; ++line) {
        const char* eol = static_cast<const char*>(std::memchr(p, '\n', static_cast<size_t>(block.end - p)));
        if (!eol) eol = block.end;
        const char* row_end = eol > p && eol[-1] == '\r' ? eol - 1 : eol;
        const char* cell = p;
        p = eol < block.end ? eol + 1 : block.end;
        if (row_end == cell) continue;  // a blank line (the last newline)
        if (block.first_data_line == 0) block.first_data_line = line;
        double* row = out + parsed * n;
        size_t column = 0;
        while (true) {
            const char* cell_end = static_cast<const char*>(std::memchr(cell, ',', static_cast<size_t>(row_end - cell)));
            if (!cell_end) cell_end = row_end;
            if (column >= n) return fail("more values than the " + std::to_string(n) + " columns of the header");
            double v = 0.0;
            const char* b = cell;
            while (b < cell_end && *b == ' ') ++b;
            if (b < cell_end && *b == '+') ++b;
            const auto r = std::from_chars(b, cell_end, v);
            const char* rest = r.ptr;
            while (rest < cell_end && *rest == ' ') ++rest;
            if (r.ec != std::errc() || rest != cell_end || !std::isfinite(v))
                return fail("column " + std::to_string(column + 1) + " " + quote(columns[column]) + ": " +
                            quote(std::string(cell, cell_end)) + " is not a finite number");
            // the glTF file and the page store 32-bit floats: a larger number would become inf there
            if (std::abs(v) > static_cast<double>(std::numeric_limits<float>::max()))
                return fail("column " + std::to_string(column + 1) + " " + quote(columns[column]) + ": " +
                            quote(std::string(cell, cell_end)) + " is beyond the range of the 32-bit floats an "
                            "animation stores (3.4e38); a motion this large is no result to watch");
            row[column++] = v;
            if (cell_end == row_end) break;
            cell = cell_end + 1;
        }
        if (column != n)
            return fail("this row has " + std::to_string(column) + " values for the " + std::to_string(n) +
                        " columns of the header (a truncated file?)");
        if (parsed > 0 && !(row[0] > previous_time))
            return fail("time " + std::to_string(row[0]) + " does not increase (the row before has " +
                        std::to_string(previous_time) + ")");
        previous_time = row[0];
        ++parsed;
    }
}

// Runs task(k) for k < count, on count threads (the calling thread takes k = 0).
template <class Task>
void run_parallel(size_t count, Task task) {
    std::vector<std::thread> threads;
    for (size_t k = 1; k < count; ++k) threads.emplace_back(task, k);
    task(0);
    for (std::thread& t : threads) t.join();
}

}  // namespace

MotionTable read_motion_csv(const std::filesystem::path& file, unsigned threads) {
    MotionTable table;
    table.source = file.string();
    const MappedFile text(file);
    const char* p = text.data();
    const char* end = p + text.size();
    const char* eol = std::find(p, end, '\n');
    table.columns = split_header(std::string(p, eol));
    if (table.columns.empty() || table.columns[0] != "t")
        throw InputError(table.source + ":1", "the first column must be 't' (a result CSV of mbd simulate, "
                                              "kinematics or statics); got " +
                                                  quote(table.columns.empty() ? "" : table.columns[0]));
    const size_t n = table.columns.size();
    p = eol < end ? eol + 1 : end;

    // A result of several hundred MB: blocks of whole lines parsed in parallel, each straight
    // into its rows of the table (a first pass counts the rows of each block).
    const size_t bytes = static_cast<size_t>(end - p);
    if (threads == 0)  // one block per 16 MB, at most one per core
        threads = static_cast<unsigned>(std::clamp<size_t>(bytes >> 24, 1, std::max(1u, std::thread::hardware_concurrency())));
    std::vector<RowBlock> blocks(threads);
    for (size_t k = 0; k < threads; ++k) {
        const char* cut = k + 1 == threads ? end : p + bytes / threads * (k + 1);
        while (cut < end && cut[-1] != '\n') ++cut;
        blocks[k].begin = k == 0 ? p : blocks[k - 1].end;
        blocks[k].end = std::max(cut, blocks[k].begin);
    }
    run_parallel(threads, [&](size_t k) { count_rows(blocks[k]); });
    size_t line = 2, row = 0;
    for (RowBlock& block : blocks) {
        block.first_line = line;
        block.first_row = row;
        line += block.lines;
        row += block.rows;
    }
    if (row == 0) throw InputError(table.source + ":2", "the result CSV has a header but no rows");
    table.values.resize(row * n);
    run_parallel(threads, [&](size_t k) { parse_rows(blocks[k], table.columns, table.values.data() + blocks[k].first_row * n); });

    // the first error in file order: within a block, or a time that does not increase across two
    for (size_t k = 0; k < threads; ++k) {
        const RowBlock& block = blocks[k];
        if (block.parsed > 0 && block.first_row > 0) {
            const double before = table.at(block.first_row - 1, 0), now = table.at(block.first_row, 0);
            if (!(now > before))
                throw InputError(table.source + ":" + std::to_string(block.first_data_line),
                                 "time " + std::to_string(now) + " does not increase (the row before has " +
                                     std::to_string(before) + ")");
        }
        if (!block.error.empty()) throw InputError(table.source + ":" + std::to_string(block.error_line), block.error);
    }
    // a file cut inside its last line (a copy or a write that stopped) may end in a cut number
    // that still parses: every line of a complete result ends with its line end
    if (end > text.data() && end[-1] != '\n') {
        const size_t last_line = blocks.back().first_line + blocks.back().lines - 1;  // blocks follow each other
        throw InputError(table.source + ":" + std::to_string(last_line),
                         "the last line has no line end: the file was cut (an unfinished copy or write?); give the "
                         "complete result");
    }
    return table;
}

MotionTable motion_from_state(const Model& model, const State& state, const std::string& source) {
    MotionTable table;
    table.source = source;
    table.columns = motion_columns(model);
    const std::vector<double> values = motion_values(model, state);
    table.values.assign(values.begin(), values.end());
    return table;
}

std::vector<PoseColumns> match_pose_columns(const Model& model, const MotionTable& table) {
    std::map<std::string, int> index;
    for (size_t k = 0; k < table.columns.size(); ++k) index.emplace(table.columns[k], static_cast<int>(k));
    const bool planar = model.dimension == Dimension::Planar;
    const std::string scene = quote(model.source) + " (" + (planar ? "planar" : "spatial") + ")";
    const std::string where = table.source + ":1";

    // a body column (NAME.x) whose NAME is no body of the scene: the CSV of another scene
    for (size_t k = 1; k < table.columns.size(); ++k) {
        const std::string& c = table.columns[k];
        const size_t dot = c.rfind('.');
        if (dot == std::string::npos || c.substr(dot) != ".x") continue;
        const std::string owner = c.substr(0, dot);
        const size_t node = owner.rfind(".node");  // a flexible body's node: match_flexible_columns
        if (node != std::string::npos && model.flexible_body_index(owner.substr(0, node)) >= 0) continue;
        if (model.flexible_body_index(owner) >= 0) continue;  // an ffrf_body's frame (NAME.x NAME.y NAME.angle)
        if (model.body_index(owner) < 0 && owner != "ground")
            throw InputError(where, "column " + std::to_string(k + 1) + " " + quote(c) + " names no body of the scene " +
                                        scene + "; was the result made from another scene?");
    }
    std::vector<PoseColumns> out;
    for (const Body& body : model.bodies) {
        auto column = [&](const char* suffix) {
            const std::string name = body.name + suffix;
            auto it = index.find(name);
            if (it == index.end()) {
                std::string note;
                if (planar && index.count(body.name + ".e0")) note = " (the CSV has spatial columns: another scene?)";
                if (!planar && index.count(body.name + ".angle")) note = " (the CSV has planar columns: another scene?)";
                throw InputError(where, "column " + quote(name) + " is missing; the scene " + scene + " has body " +
                                            quote(body.name) + note + "; give the result CSV of this scene");
            }
            return it->second;
        };
        PoseColumns p;
        p.x = column(".x");
        p.y = column(".y");
        if (planar) {
            p.angle = column(".angle");
        } else {
            p.z = column(".z");
            const char* names[] = {".e0", ".e1", ".e2", ".e3"};
            for (int k = 0; k < 4; ++k) p.e[k] = column(names[k]);
        }
        out.push_back(p);
    }
    return out;
}

std::vector<FlexibleNodeColumns> match_flexible_columns(const Model& model, const MotionTable& table) {
    std::map<std::string, int> index;
    for (size_t k = 0; k < table.columns.size(); ++k) index.emplace(table.columns[k], static_cast<int>(k));
    const bool planar = model.dimension == Dimension::Planar;
    std::vector<FlexibleNodeColumns> out;
    for (const FlexibleBodyInstance& f : model.flexible_bodies) {
        FlexibleNodeColumns body{f.name, {}};
        for (int k = 0; k < f.body->node_count(); ++k) {
            std::array<int, 3> node{-1, -1, -1};
            for (int axis = 0; axis < (planar ? 2 : 3); ++axis) {
                const std::string name = f.name + ".node" + std::to_string(k) + "." + "xyz"[axis];
                const auto it = index.find(name);
                if (it == index.end())
                    throw InputError(table.source + ":1", "column " + quote(name) + " is missing; the scene " +
                                                              quote(model.source) + " has flexible body " + quote(f.name) +
                                                              " with " + std::to_string(f.body->node_count()) +
                                                              " nodes; give the result CSV of this scene");
                node[axis] = it->second;
            }
            body.nodes.push_back(node);
        }
        out.push_back(std::move(body));
    }
    return out;
}

Vec3 node_position(const MotionTable& table, const std::array<int, 3>& node, size_t row) {
    return Vec3(table.at(row, node[0]), table.at(row, node[1]), node[2] >= 0 ? table.at(row, node[2]) : 0.0);
}

BodyPose body_pose(const MotionTable& table, const PoseColumns& c, size_t row) {
    BodyPose pose;
    pose.position = Vec3(table.at(row, c.x), table.at(row, c.y), c.z >= 0 ? table.at(row, c.z) : 0.0);
    if (c.angle >= 0) {
        pose.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(table.at(row, c.angle), Vec3::UnitZ()));
    } else {
        // Euler parameters e0..e3 are the unit quaternion (w, x, y, z) of the body's rotation
        Eigen::Quaterniond q(table.at(row, c.e[0]), table.at(row, c.e[1]), table.at(row, c.e[2]), table.at(row, c.e[3]));
        const double norm = q.norm();
        if (norm > 0) q.coeffs() /= norm;
        pose.rotation = q;
    }
    return pose;
}

Eigen::AlignedBox3d motion_extent(const Model& model, const MotionTable& table, const std::vector<PoseColumns>& poses,
                                  const std::vector<FlexibleNodeColumns>& flexible) {
    Eigen::AlignedBox3d box;
    box.extend(Vec3::Zero());
    for (const Body& b : model.bodies) box.extend(b.position);
    for (size_t r = 0; r < table.rows(); ++r) {
        for (const PoseColumns& c : poses)
            box.extend(Vec3(table.at(r, c.x), table.at(r, c.y), c.z >= 0 ? table.at(r, c.z) : 0.0));
        for (const FlexibleNodeColumns& f : flexible)
            for (const std::array<int, 3>& node : f.nodes) box.extend(node_position(table, node, r));
    }
    return box;
}

}  // namespace mbd::viewer
