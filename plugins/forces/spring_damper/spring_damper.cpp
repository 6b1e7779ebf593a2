// Translational spring-damper-actuator (TSDA) between a point on body i and a
// point on body j (book Sec. 5.4, Eqs. 5.61-5.71; spatial Eqs. 7.116-7.124).
//
//   r = R_i + A_i u_i - R_j - A_j u_j,  l = |r|,  lhat = r / l,  ldot = lhat . rdot   (5.61-5.63, 5.71)
//   f = k (l - l0) + c ldot + f_a(t)     positive = tension (pulls the points together)
//   delta W = -f delta l  =>  Q_i = -f [lhat; (A_theta_i u_i) . lhat],  Q_j = +f [lhat; (A_theta_j u_j) . lhat]  (5.70)
//   spatial (moments in body axes): Q_i = -f [lhat; u_i x (A_i^T lhat)],  Q_j = +f [lhat; u_j x (A_j^T lhat)]
//
// Keys: stiffness k (>= 0, required), damping c (>= 0, default 0), rest_length l0
// (>= 0, default: the distance of the points at t = 0), force f_a (optional time
// function, e.g. a number or {type: harmonic, ...}). Attachment points: the
// markers the core builds from `points` (body frames); without markers, the
// mass centres. Potential 1/2 k (l - l0)^2; conservative iff c = 0 and no actuator.
// Degenerate length: when l < 1e-12 the direction lhat is undefined; the element
// then uses lhat = 0 (no force, zero Jacobians) rather than throwing, so that a
// simulation passing through coincident points continues.
#include <mbd/sdk/force_support.hpp>
#include <mbd/sdk/plugin.hpp>
#include <mbd/sdk/plugin_keys.hpp>

#include <cmath>
#include <memory>

namespace {

using namespace mbd;
using namespace mbd::force_support;

class SpringDamper final : public SpringDamperElement<SpringDamper> {
public:
    explicit SpringDamper(const ForceSpec& spec) : SpringDamperElement(spec, "force") {
        for (int k = 0; k < 2; ++k) u_[k] = ends_[k].u_bar;
        if (dim_ == Dimension::Planar) u_[0].z() = u_[1].z() = 0.0;
        const double l_initial =
            (initial_point(spec.bodies[0], u_[0]) - initial_point(spec.bodies[1], u_[1])).norm();
        if (spec.params.has("rest_length")) {
            l0_ = non_negative(spec, "rest_length");
        } else {
            if (l_initial < 1e-12)
                fail(spec, "the two points coincide at t = 0, so the rest length cannot be taken from the "
                           "initial configuration; give 'rest_length' (and move the points apart: the spring "
                           "direction is undefined at zero length)");
            l0_ = l_initial;
        }
    }

    double potential_energy(const BodyStates& b) const override {
        double l;
        if (!b.planar_bodies.empty())
            l = (b.planar(0).point(u_[0].head<2>()) - b.planar(1).point(u_[1].head<2>())).norm();
        else
            l = (b.spatial(0).point(u_[0]) - b.spatial(1).point(u_[1])).norm();
        return 0.5 * sda_.k * (l - l0_) * (l - l0_);
    }

    template <class S>
    VX<S> generalized(const PlanarStates<S>& s, double fa) const {
        using std::sqrt;
        const Vec2 ui = u_[0].head<2>(), uj = u_[1].head<2>();
        const V2<S> r = s[0].point(ui) - s[1].point(uj);  // (5.62)
        VX<S> Q = VX<S>::Zero(6);
        const S l2 = r.squaredNorm();
        if (value_of(l2) < 1e-24) return Q;  // degenerate length: no direction
        const S l = sqrt(l2);
        const V2<S> lhat = r / l;
        const V2<S> rdot = s[0].point_velocity(ui) - s[1].point_velocity(uj);
        const S ldot = lhat.dot(rdot);                         // (5.71)
        const S f = sda_.k * (l - l0_) + sda_.c * ldot + fa;            // (5.61)
        Q.template segment<2>(0) = -f * lhat;                   // (5.70a)
        Q[2] = -f * s[0].A_theta_u(ui).dot(lhat);
        Q.template segment<2>(3) = f * lhat;                    // (5.70b)
        Q[5] = f * s[1].A_theta_u(uj).dot(lhat);
        return Q;
    }
    template <class S>
    VX<S> generalized(const SpatialStates<S>& s, double fa) const {
        using std::sqrt;
        const V3<S> r = s[0].point(u_[0]) - s[1].point(u_[1]);
        VX<S> Q = VX<S>::Zero(12);
        const S l2 = r.squaredNorm();
        if (value_of(l2) < 1e-24) return Q;
        const S l = sqrt(l2);
        const V3<S> lhat = r / l;
        const V3<S> rdot = s[0].point_velocity(u_[0]) - s[1].point_velocity(u_[1]);
        const S ldot = lhat.dot(rdot);
        const S f = sda_.k * (l - l0_) + sda_.c * ldot + fa;                     // (7.116)
        Q.template segment<3>(0) = -f * lhat;                            // (7.121-7.124), moments
        Q.template segment<3>(3) = -f * u_[0].cast<S>().cross(s[0].A.transpose() * lhat);  // in body axes
        Q.template segment<3>(6) = f * lhat;
        Q.template segment<3>(9) = f * u_[1].cast<S>().cross(s[1].A.transpose() * lhat);
        return Q;
    }

private:
    Vec3 u_[2];
    double l0_ = 0;
};

std::unique_ptr<Force> make_spring_damper(const ForceSpec& spec) { return std::make_unique<SpringDamper>(spec); }

}  // namespace

MBD_FORCE_PLUGIN(spring_damper, make_spring_damper)

// The keys of a scene entry (mbd/sdk/plugin_keys.hpp): `mbd plugin check` builds its test scene
// from the examples; docs/scene-format.md is checked against them (tests/test_plugin_keys.cpp).
namespace {
const mbd::PluginKey spring_damper_keys[] = {
    {"stiffness", "k (N/m), >= 0", nullptr, "100"},
    {"damping", "c (N s/m), >= 0", "0", "2", nullptr, true},
    {"rest_length", "l0 (m), >= 0", "the points' distance at t = 0", "0.35"},
    {"force", "an actuator force (N, positive: tension), a time function", "none", "{type: harmonic, amplitude: 1, frequency: 3}"},
    {}};
}  // namespace

MBD_FORCE_KEYS(spring_damper, "a translational spring-damper-actuator between two points", mbd::kTwoBodies, mbd::kPlanarAndSpatial, spring_damper_keys)
