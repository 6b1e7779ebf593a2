// A result CSV (the column contract of mbd/csv.hpp) read back for animation, and the
// pose of every body at each row.
#pragma once

#include <mbd/model.hpp>

#include <Eigen/Geometry>

#include <array>
#include <filesystem>
#include <memory>
#include <new>
#include <string>
#include <utility>
#include <vector>

namespace mbd::viewer {

// An allocator whose resize leaves the values uninitialised: the reader writes every one,
// and zeroing a table of several hundred MB first would cost about as much as parsing it.
template <class T>
struct UninitializedAllocator : std::allocator<T> {
    template <class U>
    struct rebind {
        using other = UninitializedAllocator<U>;
    };
    UninitializedAllocator() = default;
    template <class U>
    UninitializedAllocator(const UninitializedAllocator<U>&) noexcept {}
    template <class U>
    void construct(U* p) noexcept {
        ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
};

struct MotionTable {
    std::string source;                 // the file it came from (for messages)
    std::vector<std::string> columns;
    std::vector<double, UninitializedAllocator<double>> values;  // row-major, rows() x columns.size()

    size_t rows() const { return columns.empty() ? 0 : values.size() / columns.size(); }
    double at(size_t row, size_t column) const { return values[row * columns.size() + column]; }
};

// Reads a result CSV; a malformed cell, a short row or a time that does not increase
// throws InputError naming file:line and the column (the first such place in the file).
// The rows are parsed in `threads` blocks at once (0: one per 16 MB, at most one per core).
MotionTable read_motion_csv(const std::filesystem::path& file, unsigned threads = 0);

// One row from a state (mbd statics): the same columns mbd simulate writes.
MotionTable motion_from_state(const Model& model, const State& state, const std::string& source);

// Where each body's pose sits in the table: x y z (planar: z absent) and either the angle
// (planar) or e0..e3 (spatial).
struct PoseColumns {
    int x = -1, y = -1, z = -1, angle = -1;
    int e[4] = {-1, -1, -1, -1};
};

// Checks that the table's columns are those of the scene's bodies; a missing column or a
// body column the scene does not have throws InputError naming the CSV file, line 1, the
// column and the scene.
std::vector<PoseColumns> match_pose_columns(const Model& model, const MotionTable& table);

// Where each flexible body's nodes sit in the table (NAME.nodeK.x .y, spatial .z too: csv.hpp):
// per node its x, y, z columns (planar: z -1). Drawn as a tube through the nodes.
struct FlexibleNodeColumns {
    std::string name;
    std::vector<std::array<int, 3>> nodes;
};

// The same check as match_pose_columns for the flexible bodies' node columns.
std::vector<FlexibleNodeColumns> match_flexible_columns(const Model& model, const MotionTable& table);

// A node's position at a row.
Vec3 node_position(const MotionTable& table, const std::array<int, 3>& node, size_t row);

struct BodyPose {
    Vec3 position = Vec3::Zero();               // mass centre, world
    Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();  // body to world
};

BodyPose body_pose(const MotionTable& table, const PoseColumns& columns, size_t row);

// Every mass centre and flexible body's node over every row, and the initial extent of the
// scene's points.
Eigen::AlignedBox3d motion_extent(const Model& model, const MotionTable& table,
                                  const std::vector<PoseColumns>& poses,
                                  const std::vector<FlexibleNodeColumns>& flexible = {});

}  // namespace mbd::viewer
