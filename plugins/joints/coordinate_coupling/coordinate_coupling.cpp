// The coordinate_coupling joint plugin (spatial): the coordinate of one one-coordinate joint
// (the follower) tied linearly to that of another (the leader),
//     q_f = multiplier * q_l + offset,
// as URDF's <mimic> and MuJoCo's <equality joint=...> (its linear part) mean. One row:
//     C = (s_f + start_f) - multiplier (s_l + start_l) - offset,
// where s is the relative motion of a side's two bodies since the scene's initial configuration
// (angle about its axis: spatial_primitives.hpp angle_about_z; or travel along it: travel_along_z
// of the side's frame origin), and start the joint position there (the importer passes the source
// joint positions, so offset keeps the source's meaning). J, gamma: those of s_f minus multiplier
// times those of s_l (both linear combinations, spatial_primitives.hpp combine); C_t = 0.
// Each side's frame is given as for a revolute or prismatic joint (point, axis in world at t = 0)
// and names the two of the joint's bodies it lies between. The joints that carry the two
// coordinates (revolute, prismatic) are separate joints; this one adds the coupling row only.
// An angle lies in (-pi, pi] (atan2), so a side must turn less than half a turn from its start.
#include <mbd/sdk/plugin.hpp>
#include <mbd/sdk/plugin_keys.hpp>
#include <mbd/sdk/rotation.hpp>
#include <mbd/sdk/spatial_primitives.hpp>

#include <cmath>
#include <memory>
#include <string>

namespace {

using mbd::Mat3;
using mbd::Vec3;

// One coupled coordinate: which of the joint's bodies (i, j), its marker on each, angle or travel.
struct Side {
    int i = 0, j = 1;
    mbd::Marker mi, mj;
    bool angle = true;
    double start = 0.0;

    mbd::spatial::Scalar value(const mbd::BodyStates& b) const {
        const mbd::spatial::Pair pair(b.spatial(i), b.spatial(j));
        return angle ? mbd::spatial::angle_about_z(pair, mi, mj) : mbd::spatial::travel_along_z(pair, mi, mj.u_bar);
    }
};

class CoordinateCoupling final : public mbd::Joint {
public:
    CoordinateCoupling(Side follower, Side leader, double multiplier, double offset)
        : f_(std::move(follower)), l_(std::move(leader)), m_(multiplier), offset_(offset),
          periodic_(f_.angle && l_.angle && std::abs(multiplier) == 1.0) {}

    int rows() const override { return 1; }

    void evaluate(const mbd::BodyStates& b, mbd::ConstraintEval& out) const override {
        out.J.setZero();
        const mbd::spatial::Scalar sf = f_.value(b), sl = l_.value(b);
        const double C = (sf.value + f_.start) - m_ * (sl.value + l_.start) - offset_;
        out.C[0] = periodic_ ? mbd::wrap_angle(C) : C;
        scatter(f_, sf.J, 1.0, out);
        scatter(l_, sl.J, -m_, out);
        out.C_t[0] = 0.0;
        out.gamma[0] = sf.gamma - m_ * sl.gamma;
    }

    std::string row_name(int) const override { return "coupling"; }

    // Two angles coupled one to one (multiplier +-1): the row holds modulo a turn, so its residual is
    // wrapped and the two sides may pass +-pi (each angle wraps there) without the row jumping.
    double row_period(int) const override { return periodic_ ? 2.0 * M_PI : 0.0; }

private:
    // the side's 12 columns [body i, body j] into the joint's 6 per body
    static void scatter(const Side& s, const mbd::spatial::Row12& J, double weight, mbd::ConstraintEval& out) {
        out.J.block<1, 6>(0, 6 * s.i) += weight * J.segment<6>(0);
        out.J.block<1, 6>(0, 6 * s.j) += weight * J.segment<6>(6);
    }

    Side f_, l_;
    double m_, offset_;
    bool periodic_;
};

// The index in the joint's `bodies` of a side's body named `name`.
int body_index(const mbd::JointSpec& spec, const mbd::Param& list, int k, const std::string& who) {
    const std::string& name = list.items[k].text;
    for (size_t b = 0; b < spec.bodies.size(); ++b)
        if (spec.bodies[b].name == name) return static_cast<int>(b);
    list.fail(who + ": body '" + name + "' is not one of the joint's 'bodies'; list it there");
    return -1;
}

// A marker on body k for the world frame (origin, axes) at t = 0.
mbd::Marker marker_on(const mbd::BodyInfo& body, const Vec3& origin, const Mat3& axes) {
    mbd::Marker m;
    m.u_bar = body.orientation.transpose() * (origin - body.position);
    m.A_bar = body.orientation.transpose() * axes;
    return m;
}

Side read_side(const mbd::JointSpec& spec, const std::string& key, const std::string& who) {
    if (!spec.params.has(key))
        throw mbd::InputError(spec.params.location(),
                              who + " needs '" + key + ": {bodies: [a, b], point: [x, y, z], axis: [x, y, z], coordinate: angle}'");
    const mbd::Params p = spec.params.child(key);
    const std::string what = who + " " + key;
    Side s;
    if (p.has("bodies")) {  // default: the joint's first two bodies
        const mbd::Param& bodies = p.at("bodies");
        if (!bodies.is_list() || bodies.items.size() != 2)
            bodies.fail(what + ": 'bodies' must name the two bodies the " + key + " joint connects, [a, b]");
        s.i = body_index(spec, bodies, 0, what);
        s.j = body_index(spec, bodies, 1, what);
        if (s.i == s.j) bodies.fail(what + ": the two bodies must differ");
    }
    const std::string coordinate = p.string("coordinate", "angle");
    if (coordinate != "angle" && coordinate != "travel")
        p.at("coordinate").fail(what + ": 'coordinate' must be angle (a revolute joint's) or travel (a prismatic one's), got " + coordinate);
    s.angle = coordinate == "angle";
    const Vec3 origin = p.has("point") ? Vec3(p.vector("point", 3)) : Vec3::Zero();
    Vec3 z = p.vector("axis", 3);
    if (!(z.norm() > 1e-12)) p.at("axis").fail(what + ": 'axis' must not be the zero vector");
    z.normalize();
    Mat3 axes;
    axes.col(0) = mbd::any_perpendicular(z);
    axes.col(1) = z.cross(axes.col(0));
    axes.col(2) = z;
    s.mi = marker_on(spec.bodies[s.i], origin, axes);
    s.mj = marker_on(spec.bodies[s.j], origin, axes);
    s.start = p.number("start", 0.0);
    return s;
}

std::unique_ptr<mbd::Joint> make_coordinate_coupling(const mbd::JointSpec& spec) {
    const std::string who = "joint '" + spec.name + "' (coordinate_coupling)";
    if (spec.dimension != mbd::Dimension::Spatial)
        throw mbd::InputError(spec.params.location(),
                              who + " is a spatial joint; in a planar scene couple two angles with gear_pair");
    Side follower = read_side(spec, "follower", who);
    Side leader = read_side(spec, "leader", who);
    const double multiplier = spec.params.number("multiplier", 1.0);
    const double offset = spec.params.number("offset", 0.0);
    if (!std::isfinite(multiplier) || !std::isfinite(offset))
        throw mbd::InputError(spec.params.location(), who + ": 'multiplier' and 'offset' must be finite numbers");
    return std::make_unique<CoordinateCoupling>(std::move(follower), std::move(leader), multiplier, offset);
}

}  // namespace

MBD_JOINT_PLUGIN(coordinate_coupling, make_coordinate_coupling)

// The keys of a scene entry (mbd/sdk/plugin_keys.hpp); docs/scene-format.md is checked against them.
namespace {
const mbd::PluginKey coordinate_coupling_keys[] = {
    {"follower", "the coupled joint: {bodies: [a, b] (two of `bodies`; default their first two), point, axis (world, t = 0), coordinate: angle | travel, start: its position at t = 0 (default 0)}", nullptr,
     "{axis: [0, 0, 1], coordinate: travel}"},
    {"leader", "the joint it follows, given as `follower`", nullptr, "{axis: [0, 0, 1], coordinate: angle}"},
    {"multiplier", "q_follower = multiplier * q_leader + offset", "1", "0.01", nullptr, true},
    {"offset", "(m or rad, the follower's unit)", "0", "0"},
    {}};
}  // namespace

MBD_JOINT_KEYS(coordinate_coupling, "one joint's coordinate tied linearly to another's (URDF mimic, MJCF joint equality)",
               mbd::kTwoBodies, mbd::kSpatialOnly, coordinate_coupling_keys)
