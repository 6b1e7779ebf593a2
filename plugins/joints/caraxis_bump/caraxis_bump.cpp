// The caraxis_bump joint plugin (planar): the time-dependent constraint of the Test Set car
// axis (Mazzia & Magherini, Test Set for IVP Solvers, problem "car axis"; see
// /work/shared/reference/README.md). The bump point b(t) = (x_b, y_b), y_b = r sin(w t),
// x_b = sqrt(L^2 - y_b^2) moves on the circle of radius L about the origin, so it is carried by
// a body pinned at the origin (a separate revolute joint) whose angle relative to body i is
//   phi(t) = asin(r sin(w t) / L):       C = theta^j - theta^i - phi(t)
//   J = [0 0 -1 | 0 0 1],   C_t = -phidot,   gamma = phiddot
// (rheonomic row, book Eqs. 3.120-3.124). Written as a joint because phi(t) is not one of the
// scene's time functions. Scene keys: amplitude r, frequency w [rad/s], length L.
#include <mbd/sdk/planar_primitives.hpp>
#include <mbd/sdk/plugin.hpp>
#include <mbd/sdk/plugin_keys.hpp>

#include <cmath>
#include <memory>
#include <string>

namespace {

class CarAxisBump final : public mbd::Joint {
public:
    CarAxisBump(double r, double w, double L, double c) : a_(r / L), w_(w), c_(c) {}

    int rows() const override { return 1; }

    void evaluate(const mbd::BodyStates& b, mbd::ConstraintEval& out) const override {
        using namespace mbd::planar;
        clear(out);
        RowSink s(out);
        // phi = asin(u), u = a sin(w t)
        const double t = b.t;
        const double u = a_ * std::sin(w_ * t), ud = a_ * w_ * std::cos(w_ * t), udd = -w_ * w_ * u;
        const double root = std::sqrt(1.0 - u * u);
        const double phi = std::asin(u);
        const double phid = ud / root;
        const double phidd = udd / root + u * ud * ud / (root * root * root);
        s.C(0) = b.planar(1).theta - b.planar(0).theta - c_ - phi;
        s.add_J_theta(0, 0, -1.0);
        s.add_J_theta(0, 1, 1.0);
        s.add_C_t(0, -phid);
        s.gamma(0) = phidd;
    }

    std::string row_name(int) const override { return "bump angle"; }

private:
    double a_, w_, c_;
};

std::unique_ptr<mbd::Joint> make_caraxis_bump(const mbd::JointSpec& spec) {
    const std::string who = "caraxis_bump '" + spec.name + "'";
    mbd::planar::check_spec(spec, 2, 2, false);
    const double r = spec.params.number("amplitude");
    const double w = spec.params.number("frequency");
    const double L = spec.params.number("length");
    if (!(std::isfinite(r) && std::isfinite(w) && std::isfinite(L) && L > std::abs(r)))
        throw mbd::InputError(spec.params.location(), who + ": needs finite amplitude, frequency and length > |amplitude|");
    const double c = spec.bodies[1].angle - spec.bodies[0].angle;  // phi(0) = 0
    return std::make_unique<CarAxisBump>(r, w, L, c);
}

}  // namespace

MBD_JOINT_PLUGIN(caraxis_bump, make_caraxis_bump)

// The keys of a scene entry (mbd/sdk/plugin_keys.hpp): `mbd plugin check` builds its test scene
// from the examples; docs/scene-format.md is checked against them (tests/test_plugin_keys.cpp).
namespace {
const mbd::PluginKey caraxis_bump_keys[] = {
    {"amplitude", "r (m), finite", nullptr, "0.1"},
    {"frequency", "w (rad/s), finite", nullptr, "10"},
    {"length", "L (m), > |amplitude|", nullptr, "1.0"},
    {}};
}  // namespace

MBD_JOINT_KEYS(caraxis_bump, "the car axis bump: body j's angle follows asin(r sin(w t) / L)", mbd::kTwoBodies, mbd::kPlanarOnly, caraxis_bump_keys)
