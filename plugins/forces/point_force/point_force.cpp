// A force applied at a point of one body (book Eqs. 5.45-5.46; spatial 7.111-7.115).
//   planar:  Q = [F; (A u_bar) x F]  (z component; = u_bar^T A_theta^T F)
//   spatial: Q_R = F (world), Q_pi_bar = u_bar x (A^T F)  (moment in body axes)
// Keys: force: a list of 2 (planar) or 3 (spatial) components, each a number or a
// time function; frame: world (default) or body (components in body axes, turning with
// the body). The point is the marker the core builds from 'point' (body frame); without
// a marker, the mass centre. Exact Jacobians (non-zero for frame: body and for the moment
// of a world-fixed force as the body turns).
// Conservative when the force is constant and given in the world frame (a dead load): its
// potential is V = -F . r_P(q), whose gradient is -J_P^T F = -Q for any body the point moves
// with (rigid, or a material point of a flexible body). A force in body axes (a follower
// force) or one that varies in time is not conservative and has no potential here.
#include <mbd/sdk/force_support.hpp>
#include <mbd/sdk/plugin.hpp>
#include <mbd/sdk/plugin_keys.hpp>
#include <mbd/sdk/time_function.hpp>

#include <cmath>
#include <memory>
#include <string>
#include <vector>
namespace {

using namespace mbd;
using namespace mbd::force_support;

class PointForce final : public LoadedForce<PointForce, 1> {
public:
    explicit PointForce(const ForceSpec& spec) : LoadedForce(spec, "one body") {
        u_ = marker_or_centre(spec, 0).u_bar;
        const int n = dim_ == Dimension::Planar ? 2 : 3;
        if (dim_ == Dimension::Planar) u_.z() = 0.0;
        if (!spec.params.has("force")) fail(spec, "missing key 'force' (e.g. force: [0, -9.81] (planar) or [0, 0, -9.81] (spatial))");
        const Param& f = spec.params.at("force");
        if (!f.is_list() || static_cast<int>(f.items.size()) != n)
            fail(spec, "'force' must be a list of " + std::to_string(n) + " components for a " +
                           to_string(dim_) + " model (each a number or a time function)",
                 &f);
        for (int k = 0; k < n; ++k)
            components_.push_back(make_time_function(
                f.items[k], "force '" + spec.name + "' force[" + std::to_string(k) + "]"));
        body_frame_ = body_frame(spec);
        dead_load_ = !body_frame_ && all_constant(f);
    }

    bool is_conservative() const override { return dead_load_; }
    double potential_energy(const BodyStates& b) const override {
        if (!dead_load_) return 0.0;
        const Vec3 F = load(b.t);
        if (!b.planar_bodies.empty()) return -F.head<2>().dot(b.planar(0).point(u_.head<2>()));
        return -F.dot(b.spatial(0).point(u_));
    }

    // the applied force F(t), world or body components
    Vec3 load(double t) const { return components_at(components_, t); }
    template <class S>
    VX<S> generalized(const PlanarStates<S>& s, const Vec3& F) const {
        const V2<S> Fw = body_frame_ ? V2<S>(s[0].A * F.head<2>().cast<S>()) : V2<S>(F.head<2>().cast<S>());
        VX<S> Q(3);
        Q << Fw, s[0].A_theta_u(u_.head<2>()).dot(Fw);  // (5.45): u_bar^T A_theta^T F = (A u_bar) x F
        return Q;
    }
    template <class S>
    VX<S> generalized(const SpatialStates<S>& s, const Vec3& F) const {
        const V3<S> Fw = body_frame_ ? V3<S>(s[0].A * F.cast<S>()) : V3<S>(F.cast<S>());
        const V3<S> Fb = body_frame_ ? V3<S>(F.cast<S>()) : V3<S>(s[0].A.transpose() * Fw);
        VX<S> Q(6);
        Q << Fw, u_.cast<S>().cross(Fb);  // (7.111-7.115) with Gbar^T -> body-axis moment
        return Q;
    }

private:
    // True when every component is a bare number or {type: constant}.
    static bool all_constant(const Param& components) {
        for (const Param& c : components.items)
            if (!c.is_scalar() && !(c.is_map() && c.fields.count("type") && c.fields.at("type").text == "constant"))
                return false;
        return true;
    }

    Vec3 u_;
    bool body_frame_ = false;
    bool dead_load_ = false;  // constant and in world axes: conservative
    TimeComponents components_;
};

std::unique_ptr<Force> make_point_force(const ForceSpec& spec) { return std::make_unique<PointForce>(spec); }

}  // namespace

MBD_FORCE_PLUGIN(point_force, make_point_force)

// The keys of a scene entry (mbd/sdk/plugin_keys.hpp): `mbd plugin check` builds its test scene
// from the examples; docs/scene-format.md is checked against them (tests/test_plugin_keys.cpp).
namespace {
const mbd::PluginKey point_force_keys[] = {
    {"force", "2 (planar) or 3 (spatial) components, each a number or a time function", nullptr, "[1, -2]", "[1, -2, 0.5]"},
    {"frame", "world or body (components in body axes)", "world", "body", nullptr, true},
    {}};
}  // namespace

MBD_FORCE_KEYS(point_force, "a force at a point of one body", mbd::kOneBody, mbd::kPlanarAndSpatial, point_force_keys)
