// Coulomb friction between two bodies along a contact line (book Sec. 5.5, Eq. 5.74),
// with static and kinetic coefficients and the regularized law of mbd/sdk/coulomb_law.hpp.
//
// The contact point P is the force's marker on the first body (i), the contact line
// the marker's axis t = A_i A_bar_i e (e = x planar, z spatial: the scene's `axis`, as for
// a joint; it turns with body i). The sliding velocity
// is that of P on i relative to the material point of j at P (Eq. 5.74's v_r):
//   v_r = (Rdot_i + omega_i x (P - R_i) - Rdot_j - omega_j x (P - R_j)) . t
// and the friction force on i is F = -mu(v_r) F_n t, on j +mu(v_r) F_n t, both applied
// at P; a force is a sliding vector, so this is equipollent to the contact's friction
// (L6355). Generalized forces as for a point force (Eqs. 5.45-5.46; spatial 7.111-7.115).
//
// Keys: normal_force F_n (>= 0; a number or a time function: the load pressing the two
// surfaces together, e.g. m g cos(alpha) for a block on an incline), or instead load_joint:
// the prismatic (or other) joint between the two bodies whose reaction force normal to the
// contact line is F_n, solved with the multipliers (friction in a guide: F = mu_k N with N
// the normal reaction; kit reaction_loads.hpp), static_friction
// mu_s, kinetic_friction mu_k (0 <= mu_k <= mu_s), stiction_velocity v_s (> 0, default
// 1e-6 m/s), and the frame: `point` with `axis` (world, at t = 0: the contact point and
// the direction of the contact line). Not conservative; exact Jacobians.
#include <mbd/sdk/coulomb_law.hpp>

#include <mbd/sdk/force_support.hpp>
#include <mbd/sdk/plugin.hpp>
#include <mbd/sdk/plugin_keys.hpp>

#include <memory>
#include <string>

namespace {

using namespace mbd;
using namespace mbd::force_support;

template <class S>
S cross2(const V2<S>& a, const V2<S>& b) {
    return a.x() * b.y() - a.y() * b.x();
}

class CoulombFriction final : public LoadedForce<CoulombFriction, 2> {
public:
    explicit CoulombFriction(const ForceSpec& spec)
        : LoadedForce(spec, "two bodies [i, j]"),
          normal_(spec, "the load pressing the surfaces together, N; e.g. m g cos(angle)") {
        const Marker& m = marker_or_centre(spec, 0);
        u_ = m.u_bar;
        t_bar_ = dim_ == Dimension::Planar ? m.axis_x() : m.axis_z();  // along `axis`, as for a joint
        if (dim_ == Dimension::Planar) {
            u_.z() = 0.0;
            t_bar_.z() = 0.0;
        }
        law_.mu_static = non_negative(spec, "static_friction");
        law_.mu_kinetic = non_negative(spec, "kinetic_friction");
        if (law_.mu_kinetic > law_.mu_static)
            fail(spec, "'kinetic_friction' (" + std::to_string(law_.mu_kinetic) + ") must not exceed 'static_friction' (" +
                           std::to_string(law_.mu_static) + ")",
                 &spec.params.at("kinetic_friction"));
        law_.stiction_velocity = number_or(spec, "stiction_velocity", 1e-6);
        if (!(law_.stiction_velocity > 0.0))
            fail(spec, "'stiction_velocity' must be positive (the sliding speed below which the contact sticks)",
                 &spec.params.at("stiction_velocity"));
    }

    // the given normal load F_n(t) (0 with a load_joint: then evaluate_at_load carries it)
    double load(double t) const { return normal_.at(t); }
    std::string load_joint() const override { return normal_.joint(); }
    bool is_friction() const override { return true; }
    Vec3 load_axis(const BodyStates& b) const override {  // the contact line t, world
        if (dim_ == Dimension::Spatial) return spatial_states<double>(b)[0].A * t_bar_;
        const V2<double> t = planar_states<double>(b)[0].A * t_bar_.head<2>();
        return Vec3(t.x(), t.y(), 0.0);
    }
    void evaluate_at_load(const BodyStates& b, double normal, Eigen::Ref<Eigen::VectorXd> Q) const override {
        add_value(b, [&](const auto& s) { return generalized(s, normal); }, Q);
    }

    template <class S>
    VX<S> generalized(const PlanarStates<S>& s, double normal) const {
        const V2<S> P = s[0].point(u_.head<2>());
        const V2<S> t = s[0].A * t_bar_.head<2>().cast<S>();
        const V2<S> ri = P - s[0].R, rj = P - s[1].R;
        const V2<S> vi = s[0].Rdot + V2<S>(-ri.y(), ri.x()) * s[0].omega;
        const V2<S> vj = s[1].Rdot + V2<S>(-rj.y(), rj.x()) * s[1].omega;
        const V2<S> F = -law_.coefficient(S((vi - vj).dot(t))) * normal * t;  // on i (5.74)
        VX<S> Q(6);
        Q << F, cross2(ri, F), -F, -cross2(rj, F);  // (5.45-5.46) at P
        return Q;
    }
    template <class S>
    VX<S> generalized(const SpatialStates<S>& s, double normal) const {
        const V3<S> P = s[0].point(u_);
        const V3<S> t = s[0].A * t_bar_.cast<S>();
        const V3<S> ri = P - s[0].R, rj = P - s[1].R;
        const V3<S> vi = s[0].Rdot + s[0].omega().cross(ri);
        const V3<S> vj = s[1].Rdot + s[1].omega().cross(rj);
        const V3<S> F = -law_.coefficient(S((vi - vj).dot(t))) * normal * t;
        VX<S> Q(12);  // moments in body axes (7.111-7.115)
        Q << F, V3<S>(s[0].A.transpose() * ri).cross(V3<S>(s[0].A.transpose() * F)), -F,
            -V3<S>(s[1].A.transpose() * rj).cross(V3<S>(s[1].A.transpose() * F));
        return Q;
    }

private:
    static double number_or(const ForceSpec& spec, const std::string& key, double fallback) {
        return number(spec, key, &fallback);
    }
    friction::NormalLoad normal_;
    Vec3 u_, t_bar_;
    friction::CoulombLaw law_;
};

std::unique_ptr<Force> make_coulomb_friction(const ForceSpec& spec) {
    return std::make_unique<CoulombFriction>(spec);
}

}  // namespace

MBD_FORCE_PLUGIN(coulomb_friction, make_coulomb_friction)

// The keys of a scene entry (mbd/sdk/plugin_keys.hpp): `mbd plugin check` builds its test scene
// from the examples; docs/scene-format.md is checked against them (tests/test_plugin_keys.cpp).
namespace {
const mbd::PluginKey coulomb_friction_keys[] = {
    {"normal_force", "F_n (N), >= 0, a number or a time function; or load_joint", "none: give normal_force or load_joint", "10", nullptr, true},
    {"load_joint", "the joint between the two bodies whose reaction is F_n (augmented formulation only); or normal_force", "none: give normal_force or load_joint", "guide"},
    {"static_friction", "mu_s, >= 0", nullptr, "0.3"},
    {"kinetic_friction", "mu_k, 0 <= mu_k <= mu_s", nullptr, "0.2"},
    {"stiction_velocity", "v_s (> 0): the regularised law reaches mu_s at this sliding speed", "1e-6", "0.5", nullptr, true},
    {}};
}  // namespace

MBD_FORCE_KEYS(coulomb_friction, "dry friction along a contact line of body i", mbd::kTwoBodies, mbd::kPlanarAndSpatial, coulomb_friction_keys)
