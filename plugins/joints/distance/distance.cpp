// The distance joint plugin (planar): a massless rigid rod between point P on body i and
// point Q on body j, |r_Q - r_P| = L, written squared so that it is smooth at any length:
//   C = d^T d - L^2,   d = r_Q^j - r_P^i = R^j + A^j u_bar^j - R^i - A^i u_bar^i
//   J = 2 d^T [ -I | -A_theta^i u_bar^i | I | A_theta^j u_bar^j ]
//   Cddot = J vdot + 2 ddot^T ddot + 2 d^T (w_i^2 A^i u_bar^i - w_j^2 A^j u_bar^j), so
//   gamma = -2 ddot^T ddot - 2 d^T (w_i^2 A^i u_bar^i - w_j^2 A^j u_bar^j).
// Scene keys: points: [[x_i, y_i], [x_j, y_j]] in body frames (default: the mass centres);
// length: L (default: the points' distance at t = 0). Used by the Test Set car axis
// (scenes/bench/car-axis.yaml: the axle between the wheels). No coordinate, a loop row.
#include <mbd/sdk/planar_primitives.hpp>
#include <mbd/sdk/plugin.hpp>
#include <mbd/sdk/plugin_keys.hpp>

#include <cmath>
#include <memory>
#include <string>

namespace {

using mbd::Vec2;

class Distance final : public mbd::Joint {
public:
    Distance(const Vec2& u_i, const Vec2& u_j, double length) : u_i_(u_i), u_j_(u_j), length_(length) {}

    int rows() const override { return 1; }

    void evaluate(const mbd::BodyStates& b, mbd::ConstraintEval& out) const override {
        using namespace mbd::planar;
        clear(out);
        RowSink s(out);
        const mbd::PlanarBody& bi = b.planar(0);
        const mbd::PlanarBody& bj = b.planar(1);
        const Vec2 ui = bi.A * u_i_, uj = bj.A * u_j_;
        const Vec2 d = bj.R + uj - bi.R - ui;
        const Vec2 dd = bj.point_velocity(u_j_) - bi.point_velocity(u_i_);
        s.C(0) = d.squaredNorm() - length_ * length_;
        s.add_J_R(0, 0, -2.0 * d);
        s.add_J_theta(0, 0, -2.0 * d.dot(bi.A_theta * u_i_));
        s.add_J_R(0, 1, 2.0 * d);
        s.add_J_theta(0, 1, 2.0 * d.dot(bj.A_theta * u_j_));
        s.gamma(0) = -2.0 * dd.squaredNorm() -
                     2.0 * d.dot(bi.omega * bi.omega * ui - bj.omega * bj.omega * uj);
    }

    std::string row_name(int) const override { return "distance"; }

private:
    Vec2 u_i_, u_j_;
    double length_;
};

std::unique_ptr<mbd::Joint> make_distance(const mbd::JointSpec& spec) {
    const std::string who = "distance '" + spec.name + "'";
    mbd::planar::check_spec(spec, 2, 2, false);
    Vec2 u_i = Vec2::Zero(), u_j = Vec2::Zero();
    if (spec.params.has("points")) {
        const mbd::Param& p = spec.params.at("points");
        if (!p.is_list() || p.items.size() != 2) p.fail(who + ": 'points' must be [[x_i, y_i], [x_j, y_j]]");
        u_i = p.items[0].as_vector("points", 2, who);
        u_j = p.items[1].as_vector("points", 2, who);
    }
    const auto world = [&](int k, const Vec2& u) {
        const double a = spec.bodies[k].angle;
        return Vec2(spec.bodies[k].position.x() + std::cos(a) * u.x() - std::sin(a) * u.y(),
                    spec.bodies[k].position.y() + std::sin(a) * u.x() + std::cos(a) * u.y());
    };
    double length = (world(1, u_j) - world(0, u_i)).norm();
    if (spec.params.has("length")) length = spec.params.number("length");
    if (!(std::isfinite(length) && length > 0.0))
        throw mbd::InputError(spec.params.location(), who + ": 'length' must be positive");
    return std::make_unique<Distance>(u_i, u_j, length);
}

}  // namespace

MBD_JOINT_PLUGIN(distance, make_distance)

// The keys of a scene entry (mbd/sdk/plugin_keys.hpp): `mbd plugin check` builds its test scene
// from the examples; docs/scene-format.md is checked against them (tests/test_plugin_keys.cpp).
namespace {
const mbd::PluginKey distance_keys[] = {
    {"points", "[[x_i, y_i], [x_j, y_j]]: the rod's ends in their bodies' axes, from the mass centres", "both mass centres", "[[0.1, 0.2], [0.3, -0.1]]", nullptr, true},
    {"length", "the rod length (m), > 0", "the points' distance at t = 0", "0.8"},
    {}};
}  // namespace

MBD_JOINT_KEYS(distance, "a massless rigid rod between a point of each body", mbd::kTwoBodies, mbd::kPlanarOnly, distance_keys)
