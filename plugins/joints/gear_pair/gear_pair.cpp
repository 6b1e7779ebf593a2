// The gear_pair joint plugin (planar only): two spur gears i, j in mesh, their centres
// carried by body k (a carrier, or the ground when absent). No slip at the pitch point
// (book Eq. 3.103) integrated to one row (Eq. 3.104; Eq. 3.105 for a fixed carrier):
//   [(th_i - th_i0) - (th_k - th_k0)] a_i + [(th_j - th_j0) - (th_k - th_k0)] a_j = 0
// J: a_i at theta_i, a_j at theta_j, -(a_i + a_j) at theta_k; C_t = 0, gamma = 0.
// The revolute joints of the gear centres on the carrier are separate joints.
//
// Scene keys (one of):
//   radii: [a_i, a_j]  pitch radii, non-zero; a negative radius marks an internal (ring)
//                      gear, so that i and j turn in the same sense.
//   ratio: r           a_i = 1, a_j = r: dth_i = -r dth_j, i.e. r = a_j / a_i = N_j / N_i =
//                      |w_i / w_j| for an external mesh (opposite senses, r > 0); r < 0 for an
//                      internal mesh (same sense). Non-zero.
// bodies: [gear_i, gear_j] or [gear_i, gear_j, carrier]; initial angles are the bodies' angles
// in the scene. No coordinate, no relative motion (a loop constraint).
#include <mbd/sdk/planar_primitives.hpp>
#include <mbd/sdk/plugin.hpp>
#include <mbd/sdk/plugin_keys.hpp>

#include <cmath>
#include <memory>
#include <string>

namespace {

class GearPair final : public mbd::Joint {
public:
    GearPair(double a_i, double a_j, double th_i0, double th_j0, bool carrier, double th_k0)
        : a_i_(a_i), a_j_(a_j), th_i0_(th_i0), th_j0_(th_j0), carrier_(carrier), th_k0_(th_k0) {}

    int rows() const override { return 1; }

    void evaluate(const mbd::BodyStates& b, mbd::ConstraintEval& out) const override {
        using namespace mbd::planar;
        clear(out);
        body_angle(b, 0, th_i0_, out, 0, a_i_);  // Eq. 3.104
        body_angle(b, 1, th_j0_, out, 0, a_j_);
        if (carrier_) body_angle(b, 2, th_k0_, out, 0, -(a_i_ + a_j_));
    }

    std::string row_name(int) const override { return "gear contact"; }

private:
    double a_i_, a_j_, th_i0_, th_j0_;
    bool carrier_;
    double th_k0_;
};

std::unique_ptr<mbd::Joint> make_gear_pair(const mbd::JointSpec& spec) {
    const std::string who =
        mbd::planar::check_contact_spec(spec, 3, false, "spatial gears are not supported", "meshes", "with");

    const bool has_radii = spec.params.has("radii");
    const bool has_ratio = spec.params.has("ratio");
    if (has_radii == has_ratio)
        throw mbd::InputError(spec.params.location(),
                              who + " needs either 'radii: [a_i, a_j]' or 'ratio: r' (exactly one)");
    double a_i = 1.0, a_j = 1.0;
    if (has_radii) {
        const mbd::Param& p = spec.params.at("radii");
        const Eigen::VectorXd r = p.as_vector("radii", 2, who);
        if (!(std::isfinite(r[0]) && std::isfinite(r[1]) && r[0] != 0.0 && r[1] != 0.0))
            p.fail(who + ": 'radii' must be non-zero (negative for an internal gear), got [" +
                   p.items[0].text + ", " + p.items[1].text + "]");
        a_i = r[0];
        a_j = r[1];
    } else {
        const double r = spec.params.number("ratio");
        if (!(std::isfinite(r) && r != 0.0))
            spec.params.at("ratio").fail(who + ": 'ratio' must be non-zero, got " +
                                         spec.params.at("ratio").text);
        a_j = r;
    }
    const bool carrier = spec.bodies.size() == 3;
    return std::make_unique<GearPair>(a_i, a_j, spec.bodies[0].angle, spec.bodies[1].angle, carrier,
                                      carrier ? spec.bodies[2].angle : 0.0);
}

}  // namespace

MBD_JOINT_PLUGIN(gear_pair, make_gear_pair)

// The keys of a scene entry (mbd/sdk/plugin_keys.hpp): `mbd plugin check` builds its test scene
// from the examples; docs/scene-format.md is checked against them (tests/test_plugin_keys.cpp).
namespace {
const mbd::PluginKey gear_pair_keys[] = {
    {"radii", "pitch radii [a_i, a_j], non-zero; negative: an internal (ring) gear; exactly one of radii, ratio", "none: give radii or ratio", "[0.1, 0.3]", nullptr, true},
    {"ratio", "a_j / a_i with a_i = 1 (N_j / N_i; negative for an internal mesh); exactly one of radii, ratio", "none: give radii or ratio", "2"},
    {}};
}  // namespace

MBD_JOINT_KEYS(gear_pair, "two spur gears in mesh (a third body in `bodies`: the carrier)", mbd::kTwoBodies, mbd::kPlanarOnly, gear_pair_keys)
