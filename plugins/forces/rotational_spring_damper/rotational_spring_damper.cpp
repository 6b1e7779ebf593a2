// Rotational spring-damper-actuator (RSDA) between bodies i and j
// (book Eqs. 5.72-5.73, with the digest's erratum: the damping term is c_r thetadot;
// spatial form after Eqs. 7.129-7.132).
//
// Planar: angle = theta_j - theta_i - rest_angle (not wrapped: multi-turn springs work),
//   T = k angle + c (omega_j - omega_i) + T_a(t), Q_theta_j = -T, Q_theta_i = +T (5.73).
// Spatial: about the marker z axis (markers built by the core from the scene's
//   'axis', as for a revolute joint). With x_i, y_i, x_j the marker axes in world
//   coordinates, phi = atan2(y_i . x_j, x_i . x_j) (zero at the scene's initial
//   configuration) and angle = wrap(phi - rest_angle) in (-pi, pi].
//   Its exact variation is delta phi = h . (delta theta_j - delta theta_i) (world
//   virtual rotations), h = x_j x (b y_i - a x_i) / (a^2 + b^2), a = y_i . x_j,
//   b = x_i . x_j; h = z_i whenever z_j = z_i (e.g. across a revolute joint), so the
//   torque acts along the world z_i axis there, and the element stays exactly
//   conservative otherwise. phidot = h . (omega_j - omega_i).
//   T = k angle + c phidot + T_a(t); moments in body axes Q_pi_j = -T A_j^T h,
//   Q_pi_i = +T A_i^T h. (Undefined when x_j is parallel to z_i: h = 0 there.)
// Keys: stiffness (>= 0, required), damping (>= 0, default 0), rest_angle (rad;
// default: the initial relative angle), torque (optional time function).
// Potential 1/2 k angle^2; conservative iff c = 0 and no actuator. Exact Jacobians
// (planar and spatial) by automatic differentiation of the same expressions.
#include <mbd/sdk/force_support.hpp>
#include <mbd/sdk/plugin.hpp>
#include <mbd/sdk/plugin_keys.hpp>

#include <cmath>
#include <memory>

namespace {

using namespace mbd;
using namespace mbd::force_support;

class RotationalSpringDamper final : public SpringDamperElement<RotationalSpringDamper> {
public:
    explicit RotationalSpringDamper(const ForceSpec& spec) : SpringDamperElement(spec, "torque") {
        double initial;
        if (dim_ == Dimension::Planar) {
            initial = spec.bodies[1].angle - spec.bodies[0].angle;
        } else {
            const Mat3 ai = spec.bodies[0].orientation * ends_[0].A_bar;
            const Mat3 aj = spec.bodies[1].orientation * ends_[1].A_bar;
            initial = std::atan2(ai.col(1).dot(aj.col(0)), ai.col(0).dot(aj.col(0)));
        }
        rest_ = number(spec, "rest_angle", &initial);
    }

    double potential_energy(const BodyStates& b) const override {
        double angle;
        if (!b.planar_bodies.empty()) {
            angle = value_of(planar_angle(planar_states<double>(b)));
        } else {
            V3<double> h;
            angle = spatial_angle(spatial_states<double>(b), h);
        }
        return 0.5 * sda_.k * angle * angle;
    }

    template <class S>
    S planar_angle(const PlanarStates<S>& s) const {
        return s[1].theta - s[0].theta - rest_;
    }
    template <class S>
    VX<S> generalized(const PlanarStates<S>& s, double ta) const {
        const S T = sda_.k * planar_angle(s) + sda_.c * (s[1].omega - s[0].omega) + ta;  // (5.73), c_r thetadot
        VX<S> Q = VX<S>::Zero(6);
        Q[2] = T;
        Q[5] = -T;
        return Q;
    }

    // Spatial relative angle about z_i and the direction h of its gradient (world axes).
    template <class S>
    S spatial_angle(const SpatialStates<S>& s, V3<S>& h) const {
        using std::atan2;
        const M3<S> ai = s[0].A * ends_[0].A_bar.cast<S>(), aj = s[1].A * ends_[1].A_bar.cast<S>();
        const V3<S> xi = ai.col(0), yi = ai.col(1), xj = aj.col(0);
        const S a = yi.dot(xj), b = xi.dot(xj);
        const S n = a * a + b * b;
        if (value_of(n) < 1e-24) {
            h.setZero();
            return S(0);
        }
        h = xj.cross(yi * b - xi * a) / n;
        const S phi = atan2(a, b);
        // wrap (phi - rest) to (-pi, pi]; the shift is a constant, so derivatives are unchanged
        const double raw = value_of(phi) - rest_;
        return phi - rest_ + (wrap_angle(raw) - raw);
    }
    template <class S>
    VX<S> generalized(const SpatialStates<S>& s, double ta) const {
        V3<S> h;
        const S angle = spatial_angle(s, h);
        const S rate = h.dot(s[1].omega() - s[0].omega());
        const S T = sda_.k * angle + sda_.c * rate + ta;  // (7.129-7.132) with a rest angle
        VX<S> Q = VX<S>::Zero(12);
        Q.template segment<3>(3) = (s[0].A.transpose() * h) * T;
        Q.template segment<3>(9) = -(s[1].A.transpose() * h) * T;
        return Q;
    }

private:
    double rest_ = 0;
};

std::unique_ptr<Force> make_rotational_spring_damper(const ForceSpec& spec) {
    return std::make_unique<RotationalSpringDamper>(spec);
}

}  // namespace

MBD_FORCE_PLUGIN(rotational_spring_damper, make_rotational_spring_damper)

// The keys of a scene entry (mbd/sdk/plugin_keys.hpp): `mbd plugin check` builds its test scene
// from the examples; docs/scene-format.md is checked against them (tests/test_plugin_keys.cpp).
namespace {
const mbd::PluginKey rotational_spring_damper_keys[] = {
    {"stiffness", "k (N m/rad), >= 0", nullptr, "5"},
    {"damping", "c (N m s/rad), >= 0", "0", "0.05", nullptr, true},
    {"rest_angle", "the unloaded relative angle (rad)", "the initial relative angle", "0.3"},
    {"torque", "an actuator torque (N m), a time function", "none", "{type: harmonic, amplitude: 1, frequency: 3}"},
    {}};
}  // namespace

MBD_FORCE_KEYS(rotational_spring_damper, "a torsion spring-damper-actuator about the markers' axis", mbd::kTwoBodies, mbd::kPlanarAndSpatial, rotational_spring_damper_keys)
