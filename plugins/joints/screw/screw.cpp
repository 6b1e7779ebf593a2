// Screw (helical) joint (book Sec. 3.1 L2640): a cylindrical joint (Eqs. 7.168-7.170)
// plus one row coupling travel and rotation about z_i:
//   C = wrap(2 pi tau / pitch - theta) * pitch / (2 pi),
//   tau = z_i . (r_P^j - r_P^i),  theta = atan2(y_i . x_j, x_i . x_j),
// i.e. tau - (pitch / 2 pi) theta near C = 0, zero in the scene's initial
// configuration. `pitch` is the travel along z per revolution (m/rev, non-zero).
// 5 rows, 1 DOF: the angle theta. Spatial only.
#include <mbd/sdk/plugin.hpp>
#include <mbd/sdk/plugin_keys.hpp>
#include <mbd/sdk/spatial_primitives.hpp>

#include <cmath>
#include <memory>

namespace {

using namespace mbd::spatial;

class Screw : public PrimitiveJoint {
public:
    Screw(const mbd::JointSpec& spec, double pitch)
        : PrimitiveJoint(spec), lead_(pitch / (2.0 * M_PI)) {
        add_dot1(X, Z, "z-parallel-1");
        add_dot1(Y, Z, "z-parallel-2");
        add_dot2(X, "on-axis-1");
        add_dot2(Y, "on-axis-2");
        set_relative_motion(mbd::RelativeMotion{
            {{mbd::RelativeMotion::Kind::Helical, mbd::Vec3::UnitZ(), lead_}}});
    }

    int rows() const override { return primitive_rows() + 1; }

    void evaluate(const mbd::BodyStates& bodies, mbd::ConstraintEval& out) const override {
        PrimitiveJoint::evaluate(bodies, out);
        const Pair pair(bodies);
        const Scalar tau = travel_along_z(pair, marker_i(), marker_j().u_bar);
        const Scalar theta = angle_about_z(pair, marker_i(), marker_j());
        Scalar row = combine(1.0, tau, -lead_, theta);  // tau - lead * theta
        row.value = mbd::wrap_angle(row.value / lead_) * lead_;
        write(out, primitive_rows(), row);
    }

    std::string row_name(int row) const override {
        return row == primitive_rows() ? "helix" : PrimitiveJoint::row_name(row);
    }

    // the helix residual is wrapped: it jumps by one pitch half a pitch away from C = 0
    double row_period(int row) const override { return row == primitive_rows() ? 2.0 * M_PI * lead_ : 0.0; }

    bool has_coordinate() const override { return true; }
    void coordinate(const mbd::BodyStates& bodies, mbd::CoordinateEval& out) const override {
        write(out, angle_about_z(Pair(bodies), marker_i(), marker_j()), /*periodic=*/true);
    }

private:
    double lead_;  // travel per radian, pitch / (2 pi)
};

}  // namespace

std::unique_ptr<mbd::Joint> make_screw(const mbd::JointSpec& spec) {
    require_spatial_pair(spec,
                         "a screw couples rotation about and travel along one axis, which a "
                         "planar scene cannot represent; use a spatial scene, or a 'prismatic' "
                         "or 'revolute' joint with a driver");
    const double pitch = spec.params.number("pitch");
    if (!(std::isfinite(pitch) && pitch != 0.0))
        spec.params.at("pitch").fail("joint '" + spec.name +
                                     "': 'pitch' (travel along the axis per revolution, m/rev) "
                                     "must be a non-zero number, got " +
                                     spec.params.at("pitch").text);
    return std::make_unique<Screw>(spec, pitch);
}

MBD_JOINT_PLUGIN(screw, make_screw)

// The keys of a scene entry (mbd/sdk/plugin_keys.hpp): `mbd plugin check` builds its test scene
// from the examples; docs/scene-format.md is checked against them (tests/test_plugin_keys.cpp).
namespace {
const mbd::PluginKey screw_keys[] = {
    {"pitch", "travel along the axis per revolution (m), non-zero; positive: right-handed", nullptr, "0.02"},
    {}};
}  // namespace

MBD_JOINT_KEYS(screw, "a helical joint: travel along `axis` tied to the rotation about it", mbd::kTwoBodies, mbd::kSpatialOnly, screw_keys)
