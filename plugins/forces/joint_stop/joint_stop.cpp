// A unilateral stop on the relative motion of two bodies i, j (issue 19, item 4): the
// coordinate s of a revolute joint (coordinate: angle) or of a prismatic joint
// (coordinate: travel) between them, kept within [lower, upper].
//
// The coordinate, as the joints define it (docs/architecture.md, "Joint coordinates"):
//   angle, planar:  s = theta_j - theta_i (not wrapped).
//   angle, spatial: s = atan2(y_i . x_j, x_i . x_j) about marker i's z axis, zero in the
//                   scene's initial configuration (as rotational_spring_damper; limits in
//                   (-pi, pi)); its gradient is h . (dtheta_j - dtheta_i), h as there.
//   travel:         s = a_i . (R_j - r_P^i), a_i marker i's axis (planar x, spatial z),
//                   r_P^i marker i's origin; delta s = a . (dR_j - dR_i) + (a x (R_j - R_i)) . dpi_i
//                   (world virtual rotation of body i).
// Each limit is an event function, g = s - lower and g = upper - s (>= 0 inside the range),
// with gdot = grad(s) v (grad(s): the variations above against v).
//
// Two ways to stop, one or both:
//   restitution: e     an event-located impact with Newton's law gdot+ = -e gdot- (the core
//                      applies the impulse on the constrained system, contact_events.hpp).
//   law: hunt_crossley a compliant force while the limit is passed by delta = -g > 0:
//                      F = delta^n (k + c deltadot), never pulling (F >= 0), along the
//                      coordinate back into the range (Hunt & Crossley 1975: damping
//                      proportional to delta^n, so the force is continuous at contact onset).
//                      Keys stiffness k > 0, exponent n >= 1 (default 1.5), damping c >= 0
//                      (default 0). The onset is an event as well: no step straddles the kink.
// With both, an impact whose rebound e |gdot-| is below rest_velocity (default 1e-3 per
// second, in the coordinate's unit) comes to rest and the compliant law holds the contact.
// Potential k delta^(n+1) / (n+1); conservative without damping. Exact Jacobians.
#include <mbd/sdk/force_support.hpp>
#include <mbd/sdk/plugin.hpp>
#include <mbd/sdk/plugin_keys.hpp>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

namespace {

using namespace mbd;
using namespace mbd::force_support;

constexpr double kPi = 3.14159265358979323846;

struct Limit {
    std::string name;  // "lower" / "upper"
    double value;
    double sign;       // g = sign (s - value): +1 lower, -1 upper
};

class JointStop final : public LoadedForce<JointStop, 2> {
public:
    explicit JointStop(const ForceSpec& spec) : LoadedForce(spec, "two bodies [i, j]") {
        for (int k = 0; k < 2; ++k) marker_[k] = marker_or_centre(spec, k);
        read_coordinate(spec);
        read_limits(spec);
        read_laws(spec);
    }

    int load(double) const { return 0; }  // nothing depends on time

    // --- the force: the compliant law of every passed limit
    template <class States>
    auto generalized(const States& s, int) const {
        using S = typename std::decay_t<decltype(s[0].R)>::Scalar;
        VX<S> grad;
        const S coordinate = coordinate_and_gradient(s, grad);
        VX<S> Q = VX<S>::Zero(grad.size());
        if (!compliant_) return Q;
        const S rate = grad.dot(velocities(s));
        for (const Limit& limit : limits_) {
            const S delta = -limit.sign * (coordinate - limit.value);  // depth past the limit
            if (!(value_of(delta) > 0.0)) continue;
            using std::pow;
            const S depth_n = pow(delta, exponent_);
            S force = depth_n * (stiffness_ + damping_ * (-limit.sign * rate));
            if (value_of(force) < 0.0) continue;  // separating faster than the law pushes: no pull
            Q += (limit.sign * force) * grad;
        }
        return Q;
    }
    double potential_energy(const BodyStates& b) const override {
        if (!compliant_) return 0.0;
        const double s = coordinate_value(b);
        double V = 0.0;
        for (const Limit& limit : limits_) {
            const double delta = -limit.sign * (s - limit.value);
            if (delta > 0.0) V += stiffness_ * std::pow(delta, exponent_ + 1.0) / (exponent_ + 1.0);
        }
        return V;
    }
    bool is_conservative() const override { return damping_ == 0.0; }

    // --- events: one per limit
    int event_count() const override { return static_cast<int>(limits_.size()); }
    std::string event_name(int event) const override { return limits_.at(event).name; }
    void event_values(const BodyStates& b, Eigen::Ref<Eigen::VectorXd> g) const override {
        const double s = coordinate_value(b);
        for (size_t k = 0; k < limits_.size(); ++k) g[k] = limits_[k].sign * (s - limits_[k].value);
    }
    EventImpact event_impact(int event, const BodyStates& b, Eigen::Ref<Eigen::VectorXd> G) const override {
        VX<double> grad;
        if (!b.planar_bodies.empty())
            coordinate_and_gradient(planar_states<double>(b), grad);
        else
            coordinate_and_gradient(spatial_states<double>(b), grad);
        G = limits_.at(event).sign * grad;
        return EventImpact{impacts_, restitution_, rest_velocity_, compliant_};
    }

private:
    double coordinate_value(const BodyStates& b) const {
        VX<double> grad;
        if (!b.planar_bodies.empty()) return coordinate_and_gradient(planar_states<double>(b), grad);
        return coordinate_and_gradient(spatial_states<double>(b), grad);
    }

    // The stacked velocities [v_i; v_j] the gradient acts on.
    template <class S>
    static VX<S> velocities(const PlanarStates<S>& s) {
        VX<S> v(6);
        for (int k = 0; k < 2; ++k) v.template segment<3>(3 * k) << s[k].Rdot, s[k].omega;
        return v;
    }
    template <class S>
    static VX<S> velocities(const SpatialStates<S>& s) {
        VX<S> v(12);
        for (int k = 0; k < 2; ++k) v.template segment<6>(6 * k) << s[k].Rdot, s[k].wbar;
        return v;
    }

    template <class S>
    S coordinate_and_gradient(const PlanarStates<S>& s, VX<S>& grad) const {
        grad = VX<S>::Zero(6);
        if (!travel_) {
            grad[2] = S(-1);
            grad[5] = S(1);
            return s[1].theta - s[0].theta;
        }
        const double angle = marker_[0].angle;
        const V2<S> a = s[0].A * Vec2(std::cos(angle), std::sin(angle)).cast<S>();
        const V2<S> d = s[1].R - s[0].R;
        grad.template segment<2>(0) = -a;
        grad[2] = a.x() * d.y() - a.y() * d.x();
        grad.template segment<2>(3) = a;
        return a.dot(s[1].R - s[0].point(marker_[0].u_bar2()));
    }
    template <class S>
    S coordinate_and_gradient(const SpatialStates<S>& s, VX<S>& grad) const {
        grad = VX<S>::Zero(12);
        if (!travel_) {
            using std::atan2;
            const M3<S> ai = s[0].A * marker_[0].A_bar.cast<S>(), aj = s[1].A * marker_[1].A_bar.cast<S>();
            const V3<S> xi = ai.col(0), yi = ai.col(1), xj = aj.col(0);
            const S a = yi.dot(xj), b = xi.dot(xj);
            const S n = a * a + b * b;
            if (value_of(n) < 1e-24) return S(0);  // x_j along z_i: the angle is undefined (gradient 0)
            const V3<S> h = xj.cross(yi * b - xi * a) / n;
            grad.template segment<3>(3) = -(s[0].A.transpose() * h);
            grad.template segment<3>(9) = s[1].A.transpose() * h;
            return atan2(a, b);
        }
        const V3<S> a = s[0].A * marker_[0].axis_z().cast<S>();
        const V3<S> d = s[1].R - s[0].R;
        grad.template segment<3>(0) = -a;
        grad.template segment<3>(3) = s[0].A.transpose() * a.cross(d);
        grad.template segment<3>(6) = a;
        return a.dot(s[1].R - s[0].point(marker_[0].u_bar));
    }

    void read_coordinate(const ForceSpec& spec) {
        const std::string c = spec.params.has("coordinate") ? spec.params.string("coordinate") : "angle";
        if (c != "angle" && c != "travel")
            fail(spec, "'coordinate' must be 'angle' (a revolute joint's rotation) or 'travel' (a prismatic "
                       "joint's translation), got '" + c + "'",
                 &spec.params.at("coordinate"));
        travel_ = c == "travel";
    }
    void read_limits(const ForceSpec& spec) {
        for (const char* key : {"lower", "upper"}) {
            if (!spec.params.has(key)) continue;
            const double value = number(spec, key);
            if (!std::isfinite(value)) fail(spec, "'" + std::string(key) + "' must be finite", &spec.params.at(key));
            if (dim_ == Dimension::Spatial && !travel_ && !(std::abs(value) < kPi))
                fail(spec, "'" + std::string(key) + "' must lie in (-pi, pi): the spatial relative angle is "
                           "measured in that range", &spec.params.at(key));
            limits_.push_back({key, value, std::string(key) == "lower" ? 1.0 : -1.0});
        }
        if (limits_.empty()) fail(spec, "give 'lower' and/or 'upper', the limits of the stop's " +
                                            std::string(travel_ ? "travel (m)" : "angle (rad)"));
        if (limits_.size() == 2 && !(limits_[0].value < limits_[1].value))
            fail(spec, "'lower' must be below 'upper' (got " + std::to_string(limits_[0].value) + " and " +
                           std::to_string(limits_[1].value) + ")",
                 &spec.params.at("lower"));
    }
    void read_laws(const ForceSpec& spec) {
        impacts_ = spec.params.has("restitution");
        if (impacts_) {
            restitution_ = number(spec, "restitution");
            if (!(restitution_ >= 0.0 && restitution_ <= 1.0))
                fail(spec, "'restitution' must lie in [0, 1] (0: plastic, 1: elastic), got " +
                               std::to_string(restitution_), &spec.params.at("restitution"));
            const double fallback = 1e-3;
            rest_velocity_ = number(spec, "rest_velocity", &fallback);
            if (!(rest_velocity_ > 0.0))
                fail(spec, "'rest_velocity' must be positive (the rebound speed below which the stop rests)",
                     &spec.params.at("rest_velocity"));
        } else if (spec.params.has("rest_velocity")) {
            fail(spec, "'rest_velocity' belongs to impacts: give 'restitution' too", &spec.params.at("rest_velocity"));
        }
        compliant_ = spec.params.has("law");
        if (compliant_) {
            const std::string law = spec.params.string("law");
            if (law != "hunt_crossley")
                fail(spec, "unknown 'law' '" + law + "' (known: hunt_crossley)", &spec.params.at("law"));
            stiffness_ = number(spec, "stiffness");
            if (!(stiffness_ > 0.0))
                fail(spec, "'stiffness' must be positive", &spec.params.at("stiffness"));
            const double default_exponent = 1.5;
            exponent_ = number(spec, "exponent", &default_exponent);
            if (!(exponent_ >= 1.0))
                fail(spec, "'exponent' must be at least 1 (the force's slope at contact onset is finite)",
                     &spec.params.at("exponent"));
            damping_ = non_negative_or(spec, "damping", 0.0);
        } else {
            for (const char* key : {"stiffness", "exponent", "damping"})
                if (spec.params.has(key))
                    fail(spec, "'" + std::string(key) + "' belongs to a compliant law: add 'law: hunt_crossley'",
                         &spec.params.at(key));
        }
        if (!impacts_ && !compliant_)
            fail(spec, "say how the stop acts: 'restitution: e' (impacts) and/or 'law: hunt_crossley' with "
                       "'stiffness' (a compliant contact)");
        if (impacts_ && !compliant_ && restitution_ == 0.0)
            fail(spec, "a plastic stop ('restitution: 0') always comes to rest: give it a compliant law "
                       "('law: hunt_crossley' with 'stiffness') to hold the contact",
                 &spec.params.at("restitution"));
    }

    Marker marker_[2];
    bool travel_ = false;
    std::vector<Limit> limits_;
    bool impacts_ = false, compliant_ = false;
    double restitution_ = 0.0, rest_velocity_ = 0.0;
    double stiffness_ = 0.0, exponent_ = 1.5, damping_ = 0.0;
};

std::unique_ptr<Force> make_joint_stop(const ForceSpec& spec) { return std::make_unique<JointStop>(spec); }

}  // namespace

MBD_FORCE_PLUGIN(joint_stop, make_joint_stop)

// The keys of a scene entry (mbd/sdk/plugin_keys.hpp): `mbd plugin check` builds its test scene
// from the examples; docs/scene-format.md is checked against them (tests/test_plugin_keys.cpp).
namespace {
const mbd::PluginKey joint_stop_keys[] = {
    {"coordinate", "angle (about the frame axis) or travel (along it)", "angle", "travel"},
    {"lower", "the lower limit (rad or m); at least one of lower, upper", "none", "-0.4", nullptr, true},
    {"upper", "the upper limit, above lower", "none", "0.3", nullptr, true},
    {"restitution", "e in [0, 1]: impacts at the limit; at least one of restitution, law", "none", "0.5"},
    {"rest_velocity", "the rebound speed below which the stop rests (> 0); with restitution", "1e-3", "0.05"},
    {"law", "hunt_crossley: a compliant contact past the limit; with stiffness", "none", "hunt_crossley", nullptr, true},
    {"stiffness", "k (> 0) of the compliant law", "none: required with law", "100", nullptr, true},
    {"exponent", "n (>= 1) of the compliant law", "1.5", "1.5"},
    {"damping", "c (>= 0) of the compliant law", "0", "2"},
    {}};
}  // namespace

MBD_FORCE_KEYS(joint_stop, "a unilateral limit on the angle or travel between two bodies", mbd::kTwoBodies, mbd::kPlanarAndSpatial, joint_stop_keys)
