// A custom planar joint, written outside the mbd tree against the SDK only:
// a coupler that ties the rotation of body b to the rotation of body a by a
// ratio, (theta_b - theta_b0) = ratio * (theta_a - theta_a0), as a belt or a
// chain between two pulleys would. One constraint row.
#include <mbd/sdk/plugin.hpp>
#include <mbd/sdk/plugin_keys.hpp>

namespace {

class Coupler : public mbd::Joint {
public:
    Coupler(double ratio, double theta_a0, double theta_b0) : ratio_(ratio), a0_(theta_a0), b0_(theta_b0) {}

    int rows() const override { return 1; }

    void evaluate(const mbd::BodyStates& bodies, mbd::ConstraintEval& out) const override {
        const mbd::PlanarBody& a = bodies.planar(0);
        const mbd::PlanarBody& b = bodies.planar(1);
        out.C[0] = (b.theta - b0_) - ratio_ * (a.theta - a0_);
        out.J(0, 2) = -ratio_;  // columns: [x_a, y_a, theta_a, x_b, y_b, theta_b]
        out.J(0, 5) = 1.0;
        out.C_t[0] = 0.0;   // no explicit time dependence
        out.gamma[0] = 0.0;  // linear in the coordinates: no velocity-product terms
    }

    std::string row_name(int) const override { return "ratio"; }

private:
    double ratio_, a0_, b0_;
};

std::unique_ptr<mbd::Joint> make_coupler(const mbd::JointSpec& spec) {
    if (spec.dimension != mbd::Dimension::Planar)
        spec.params.fail("the coupler example is a planar joint; use it in a planar scene");
    if (spec.bodies.size() != 2) spec.params.fail("a coupler connects exactly two bodies: bodies: [a, b]");
    const double ratio = spec.params.number("ratio");
    if (ratio == 0.0) spec.params.at("ratio").fail("coupler ratio must not be zero");
    return std::make_unique<Coupler>(ratio, spec.bodies[0].angle, spec.bodies[1].angle);
}

}  // namespace

MBD_JOINT_PLUGIN(coupler, make_coupler)

// Its keys, for `mbd plugin check coupler` (no flags needed), `mbd plugins --keys coupler` and
// the messages about its keys (docs/plugin-sdk.md).
namespace {
const mbd::PluginKey coupler_keys[] = {
    {"ratio", "turns of body b per turn of body a, non-zero", nullptr, "2"},
    {}};  // a key without a name ends the list
}  // namespace
MBD_JOINT_KEYS(coupler, "ties the rotation of body b to body a's by a ratio", mbd::kTwoBodies, mbd::kPlanarOnly,
               coupler_keys)
