// The collision detection of one evaluation, with FCL (docs/architecture.md "Collision
// detection"): one FCL object per shape, a dynamic AABB tree over them (the broad phase,
// refitted once per evaluation to the bodies' poses), and for each candidate pair that may
// touch (different bodies, not joined, groups and masks agreeing) FCL's narrow phase giving the
// contact points, normals and depths.
//
// Each World is a workspace for one evaluation at a time: the force element keeps a pool of
// them so that threads sharing one Model never share one.
#pragma once

#include "collision_shape.hpp"

#include <mbd/sdk/body_state.hpp>

#include <memory>
#include <set>
#include <utility>
#include <vector>

namespace mbd::collision {

// One contact of a pair of shapes: the force acts at `point`, along `normal` on shape j's body
// and against it on shape i's.
struct Contact {
    int shape_i = 0, shape_j = 0;  // indices into the element's shapes
    Vec3 point = Vec3::Zero();     // world
    Vec3 normal = Vec3::Zero();    // unit, world, from shape i toward shape j
    double depth = 0.0;            // penetration, > 0
};

// Which pairs of shapes may touch: every pair of shapes on different bodies, except bodies a
// joint connects and pairs whose groups and masks exclude each other.
class PairFilter {
public:
    PairFilter() = default;
    PairFilter(const std::vector<Shape>& shapes, std::set<std::pair<int, int>> joined_bodies)
        : shapes_(&shapes), joined_(std::move(joined_bodies)) {}
    bool may_touch(int i, int j) const;

private:
    const std::vector<Shape>* shapes_ = nullptr;
    std::set<std::pair<int, int>> joined_;  // (smaller, larger) body positions
};

class World {
public:
    World(const std::vector<Shape>& shapes, const PairFilter& filter);
    ~World();
    World(const World&) = delete;
    World& operator=(const World&) = delete;

    // The contacts at the bodies' poses (positions in the element's body order).
    const std::vector<Contact>& detect(const BodyStates& bodies);
    // The contacts of shapes i and j alone (the narrow phase of that pair as detect() runs it,
    // none when they may not touch): the force Jacobians, one pair at a time.
    const std::vector<Contact>& detect_pair(int i, int j, const BodyStates& bodies);

    struct Detail;  // the FCL objects

private:
    void place(int shape, const BodyStates& bodies);  // shape's FCL object to its body's pose
    std::unique_ptr<Detail> detail_;
};

}  // namespace mbd::collision
