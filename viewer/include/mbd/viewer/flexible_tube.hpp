// The centreline of a flexible body's tube in the .glb export (issue 40): the curve through its
// nodes that the HTML page draws (viewer.js placeFlexible: a centripetal Catmull-Rom curve),
// sampled at a few points per segment, each point with a frame whose z axis is the curve's
// tangent. The glTF writer binds a ring of the tube to each point's frame (a skin joint).
#pragma once

#include <mbd/model.hpp>

#include <Eigen/Geometry>

#include <vector>

namespace mbd::viewer {

// The points of the tube's centreline per segment: node k is point k * kTubePointsPerSegment.
constexpr int kTubePointsPerSegment = 4;

// The centreline through `nodes` (at least one) at kTubePointsPerSegment points per segment,
// the last node last: (nodes - 1) * kTubePointsPerSegment + 1 points, the nodes among them
// exactly.
std::vector<Vec3> tube_centreline(const std::vector<Vec3>& nodes);

struct TubeFrame {
    Vec3 position = Vec3::Zero();
    Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();  // local z along the tangent
};

// A frame at each centreline point, its z axis along the tangent (central differences of the
// points). The frames twist as little as possible: each is the one before it along the curve
// turned by the smallest rotation between the two tangents (parallel transport), and the first
// is carried likewise from `previous` (the frames of the row before; empty at the first row),
// so that the tube does not spin about its axis from frame to frame.
std::vector<TubeFrame> tube_frames(const std::vector<Vec3>& points, const std::vector<TubeFrame>& previous);

}  // namespace mbd::viewer
