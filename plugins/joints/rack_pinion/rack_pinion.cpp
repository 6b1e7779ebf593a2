// The rack_pinion joint plugin (planar only): pinion i (pitch radius a) rolls without slip on
// rack j. Book Ex. 3.9, (th_i - th_i0) a - (x_P^j - x_P0^j) = 0, generalised so that the pinion
// centre may move and the rack may travel along any direction:
//   C = a (th_i - th_i0) - [ n . (r_P^j - R^i) - n . (r_P0^j - R0^i) ] = 0        (1 row)
// n: the rack's travel direction, the joint frame's x axis in world at t = 0 (marker j's x axis
//    turned by the rack's initial angle), held as a FIXED world direction as in the book.
// P^j: the joint point on the rack (marker j's origin), normally the pitch point.
// Sign convention: with the rack on the right of n ("below" the pinion when n points along
// +x, i.e. the pinion centre on the side of n rotated by +90 degrees), a counter-clockwise
// pinion rotation (th_i increasing) moves the rack along +n; 1 rad moves it by a. For a rack
// on the other side, give the joint the opposite axis.
// Built from the primitives body_angle + world_offset + constant:
// J = [ n^T, a | -n^T, -n^T A_theta^j u_bar^j ],  C_t = 0,  gamma = -w_j^2 n^T A^j u_bar^j
// (no pinion term: R^i is its centre).
//
// Scene keys: radius (positive pitch radius). bodies: [pinion, rack].
// No coordinate, no relative motion (a loop constraint).
#include <mbd/sdk/planar_primitives.hpp>
#include <mbd/sdk/plugin.hpp>
#include <mbd/sdk/plugin_keys.hpp>

#include <cmath>
#include <memory>
#include <string>

namespace {

class RackPinion final : public mbd::Joint {
public:
    RackPinion(double a, double th_i0, const mbd::Vec2& n, const mbd::Vec2& u_bar_j, double offset0)
        : a_(a), th_i0_(th_i0), n_(n), u_bar_j_(u_bar_j), offset0_(offset0) {}

    int rows() const override { return 1; }

    void evaluate(const mbd::BodyStates& b, mbd::ConstraintEval& out) const override {
        using namespace mbd::planar;
        clear(out);
        body_angle(b, 0, th_i0_, out, 0, a_);                                // a (th_i - th_i0)
        world_offset(b, n_, 0, mbd::Vec2::Zero(), 1, u_bar_j_, out, 0, -1.0);  // - n.(r_P^j - R^i)
        constant(offset0_, out, 0);                                          // + n.(r_P0^j - R0^i)
    }

    std::string row_name(int) const override { return "rack contact"; }

private:
    double a_, th_i0_;
    mbd::Vec2 n_, u_bar_j_;
    double offset0_;
};

std::unique_ptr<mbd::Joint> make_rack_pinion(const mbd::JointSpec& spec) {
    const std::string who =
        mbd::planar::check_contact_spec(spec, 2, true, "spatial racks are not supported", "connects", "to");
    const double a = spec.params.number("radius");
    if (!(a > 0.0 && std::isfinite(a)))
        spec.params.at("radius").fail(who + ": 'radius' (the pinion's pitch radius) must be positive, got " +
                                      spec.params.at("radius").text);

    const mbd::BodyInfo& pinion = spec.bodies[0];
    const mbd::BodyInfo& rack = spec.bodies[1];
    const mbd::Marker& mj = spec.markers[1];
    const mbd::Vec2 n = mbd::planar::unit(rack.angle + mj.angle);
    const mbd::Vec2 r_Pj0 = rack.position.head<2>() + mbd::planar_rotation(rack.angle) * mj.u_bar2();
    const double offset0 = n.dot(r_Pj0 - pinion.position.head<2>());
    return std::make_unique<RackPinion>(a, pinion.angle, n, mj.u_bar2(), offset0);
}

}  // namespace

MBD_JOINT_PLUGIN(rack_pinion, make_rack_pinion)

// The keys of a scene entry (mbd/sdk/plugin_keys.hpp): `mbd plugin check` builds its test scene
// from the examples; docs/scene-format.md is checked against them (tests/test_plugin_keys.cpp).
namespace {
const mbd::PluginKey rack_pinion_keys[] = {
    {"radius", "the pinion's pitch radius (m), > 0", nullptr, "0.05"},
    {}};
}  // namespace

MBD_JOINT_KEYS(rack_pinion, "a pinion (body i) rolling without slip on a rack (body j) along `axis`", mbd::kTwoBodies, mbd::kPlanarOnly, rack_pinion_keys)
