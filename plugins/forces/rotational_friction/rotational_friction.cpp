// Coulomb friction moment between two bodies turning about a common axis: a pin joint's
// friction (pin radius r times the load it carries, book Eq. 5.74 at the pin's surface)
// or a disk clutch (r = 2a/3 for uniform pressure over radius a, Eq. 5.76), plus a preload
// moment (seals, bearing preload) that does not depend on the load.
//
// The axis a is the force's marker axis on body i (planar: the plane normal; spatial: the
// frame's z axis, the scene's `axis`, as for a revolute joint; it turns with body i). The
// relative angular velocity about it is w_r = (omega_i - omega_j) . a, and the moment on i
// is -c(w_r) a (on j +c(w_r) a) with the friction capacity of mbd/sdk/coulomb_law.hpp:
//   c rises to M_s = mu_s r F_n + M_p within the stiction angular velocity, and falls to
//   M_k = mu_k r F_n + M_p while slipping.
// Keys: radius r (m, >= 0), normal_force F_n (N, >= 0, a number or a time function: the
// load the pin or clutch carries) or instead load_joint: the revolute (or other) joint between
// the two bodies whose reaction force transverse to the axis (the pin's radial load; planar:
// the whole reaction force) is F_n, solved with the multipliers (kit reaction_loads.hpp),
// static_friction mu_s, kinetic_friction mu_k
// (0 <= mu_k <= mu_s), preload M_p (N m, >= 0, default 0), stiction_velocity (rad/s, > 0,
// default 1e-6). Not conservative; exact Jacobians.
#include <mbd/sdk/coulomb_law.hpp>
#include <mbd/sdk/force_support.hpp>
#include <mbd/sdk/plugin.hpp>
#include <mbd/sdk/plugin_keys.hpp>

#include <memory>
#include <string>

namespace {

using namespace mbd;
using namespace mbd::force_support;

class RotationalFriction final : public LoadedForce<RotationalFriction, 2> {
public:
    explicit RotationalFriction(const ForceSpec& spec)
        : LoadedForce(spec, "two bodies [i, j]"), normal_(spec, "the load the pin or clutch carries, N") {
        axis_bar_ = marker_or_centre(spec, 0).axis_z();
        radius_ = non_negative(spec, "radius");
        mu_s_ = non_negative(spec, "static_friction");
        mu_k_ = non_negative(spec, "kinetic_friction");
        if (mu_k_ > mu_s_)
            fail(spec, "'kinetic_friction' must not exceed 'static_friction'", &spec.params.at("kinetic_friction"));
        preload_ = non_negative_or(spec, "preload", 0.0);
        const double fallback = 1e-6;
        law_.stiction_velocity = number(spec, "stiction_velocity", &fallback);
        if (!(law_.stiction_velocity > 0.0))
            fail(spec, "'stiction_velocity' must be positive (the slip rate below which the joint sticks, rad/s)",
                 &spec.params.at("stiction_velocity"));
    }

    // the friction law at t: static and kinetic moment capacities for the given load F_n(t)
    // (0 with a load_joint: then evaluate_at_load carries it)
    friction::CoulombLaw load(double t) const { return law_at(normal_.at(t)); }
    friction::CoulombLaw law_at(double n) const {
        friction::CoulombLaw law = law_;
        law.mu_static = mu_s_ * radius_ * n + preload_;  // affine in the load, as evaluate_at_load needs
        law.mu_kinetic = mu_k_ * radius_ * n + preload_;
        return law;
    }
    std::string load_joint() const override { return normal_.joint(); }
    bool is_friction() const override { return true; }
    Vec3 load_axis(const BodyStates& b) const override {  // the axis a, world (planar: the plane normal)
        if (dim_ == Dimension::Spatial) return spatial_states<double>(b)[0].A * axis_bar_;
        return Vec3::UnitZ();
    }
    void evaluate_at_load(const BodyStates& b, double n, Eigen::Ref<Eigen::VectorXd> Q) const override {
        const friction::CoulombLaw law = law_at(n);
        add_value(b, [&](const auto& s) { return generalized(s, law); }, Q);
    }

    template <class S>
    VX<S> generalized(const PlanarStates<S>& s, const friction::CoulombLaw& law) const {
        const S moment = -law.coefficient(S(s[0].omega - s[1].omega));
        VX<S> Q = VX<S>::Zero(6);
        Q[2] = moment;
        Q[5] = -moment;
        return Q;
    }
    template <class S>
    VX<S> generalized(const SpatialStates<S>& s, const friction::CoulombLaw& law) const {
        const V3<S> a = s[0].A * axis_bar_.cast<S>();
        const V3<S> M = -law.coefficient(S((s[0].omega() - s[1].omega()).dot(a))) * a;  // on i, world
        VX<S> Q = VX<S>::Zero(12);
        Q.template segment<3>(3) = s[0].A.transpose() * M;  // moments in body axes
        Q.template segment<3>(9) = -(s[1].A.transpose() * M);
        return Q;
    }

private:
    friction::NormalLoad normal_;
    Vec3 axis_bar_;
    double radius_ = 0, mu_s_ = 0, mu_k_ = 0, preload_ = 0;
    friction::CoulombLaw law_;
};

std::unique_ptr<Force> make_rotational_friction(const ForceSpec& spec) {
    return std::make_unique<RotationalFriction>(spec);
}

}  // namespace

MBD_FORCE_PLUGIN(rotational_friction, make_rotational_friction)

// The keys of a scene entry (mbd/sdk/plugin_keys.hpp): `mbd plugin check` builds its test scene
// from the examples; docs/scene-format.md is checked against them (tests/test_plugin_keys.cpp).
namespace {
const mbd::PluginKey rotational_friction_keys[] = {
    {"radius", "r (m), >= 0: the pin radius (2a/3 for a disk clutch of radius a)", nullptr, "0.02"},
    {"normal_force", "F_n (N), >= 0, a number or a time function; or load_joint", "none: give normal_force or load_joint", "100", nullptr, true},
    {"load_joint", "the joint between the two bodies whose transverse reaction is F_n (augmented only); or normal_force", "none: give normal_force or load_joint", "pin"},
    {"preload", "M_p (N m), >= 0, added to the moment capacities", "0", "0.1", nullptr, true},
    {"static_friction", "mu_s, >= 0", nullptr, "0.3"},
    {"kinetic_friction", "mu_k, 0 <= mu_k <= mu_s", nullptr, "0.2"},
    {"stiction_velocity", "v_s (> 0): the regularised law reaches mu_s at this sliding speed", "1e-6", "0.5", nullptr, true},
    {}};
}  // namespace

MBD_FORCE_KEYS(rotational_friction, "the friction moment of a pin or clutch", mbd::kTwoBodies, mbd::kPlanarAndSpatial, rotational_friction_keys)
