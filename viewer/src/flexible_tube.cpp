// The tube's centreline and its frames (flexible_tube.hpp).
#include <mbd/viewer/flexible_tube.hpp>

#include <cmath>

namespace mbd::viewer {
namespace {

// The segment from x1 to x2 of a centripetal Catmull-Rom curve (knot spacing |x_i+1 - x_i|^1/2)
// as a cubic Hermite segment, evaluated at s in [0, 1]; the tangents are those of the
// non-uniform Catmull-Rom spline rescaled to the unit parameter interval (as three.js's
// CatmullRomCurve3 'centripetal' computes them, so the .glb tube follows the page's).
Vec3 centripetal_segment(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3, double s) {
    double dt0 = std::sqrt((x1 - x0).norm()), dt1 = std::sqrt((x2 - x1).norm()), dt2 = std::sqrt((x3 - x2).norm());
    if (dt1 < 1e-4) dt1 = 1.0;  // coincident points: any finite spacing gives the same straight segment
    if (dt0 < 1e-4) dt0 = dt1;
    if (dt2 < 1e-4) dt2 = dt1;
    const Vec3 t1 = dt1 * ((x1 - x0) / dt0 - (x2 - x0) / (dt0 + dt1) + (x2 - x1) / dt1);
    const Vec3 t2 = dt1 * ((x2 - x1) / dt1 - (x3 - x1) / (dt1 + dt2) + (x3 - x2) / dt2);
    const Vec3 c2 = -3.0 * x1 + 3.0 * x2 - 2.0 * t1 - t2;
    const Vec3 c3 = 2.0 * x1 - 2.0 * x2 + t1 + t2;
    return x1 + s * (t1 + s * (c2 + s * c3));
}

}  // namespace

std::vector<Vec3> tube_centreline(const std::vector<Vec3>& nodes) {
    const size_t n = nodes.size();
    std::vector<Vec3> points;
    points.reserve((n > 0 ? n - 1 : 0) * kTubePointsPerSegment + 1);
    for (size_t k = 0; k + 1 < n; ++k) {
        // the ends extended by reflection, as an open three.js curve does
        const Vec3 before = k > 0 ? nodes[k - 1] : Vec3(2.0 * nodes[0] - nodes[1]);
        const Vec3 after = k + 2 < n ? nodes[k + 2] : Vec3(2.0 * nodes[n - 1] - nodes[n - 2]);
        points.push_back(nodes[k]);
        for (int j = 1; j < kTubePointsPerSegment; ++j)
            points.push_back(centripetal_segment(before, nodes[k], nodes[k + 1], after,
                                                 double(j) / kTubePointsPerSegment));
    }
    if (n > 0) points.push_back(nodes[n - 1]);
    return points;
}

std::vector<TubeFrame> tube_frames(const std::vector<Vec3>& points, const std::vector<TubeFrame>& previous) {
    const size_t n = points.size();
    std::vector<TubeFrame> frames(n);
    Vec3 tangent_before = previous.empty() ? Vec3::UnitZ() : Vec3(previous[0].rotation * Vec3::UnitZ());
    Eigen::Quaterniond rotation_before = previous.empty() ? Eigen::Quaterniond::Identity() : previous[0].rotation;
    for (size_t i = 0; i < n; ++i) {
        Vec3 tangent = points[std::min(i + 1, n - 1)] - points[i > 0 ? i - 1 : 0];
        // coincident points (or a single node) have no tangent: the one before is kept
        tangent = tangent.norm() > 0.0 ? Vec3(tangent.normalized()) : tangent_before;
        frames[i].position = points[i];
        frames[i].rotation = (Eigen::Quaterniond::FromTwoVectors(tangent_before, tangent) * rotation_before).normalized();
        tangent_before = tangent;
        rotation_before = frames[i].rotation;
    }
    return frames;
}

}  // namespace mbd::viewer
