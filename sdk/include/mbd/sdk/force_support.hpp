// Helpers for force plugins: forces written once as templates on the scalar type,
// evaluated with doubles for Q and with forward-mode automatic differentiation
// (Eigen AutoDiffScalar) for the exact Jacobians dQ/dq and dQ/dv, plus parameter
// readers with scene locations. Used by every plugins/forces/<type>.
#pragma once

#include <mbd/sdk/force.hpp>
#include <mbd/sdk/params.hpp>
#include <mbd/sdk/time_function.hpp>

#include <boost/container/static_vector.hpp>
#include <unsupported/Eigen/AutoDiff>

#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

// ---------------------------------------------------------------------------
// Generalized forces are written once, as templates on the scalar type S, of
// per-body states (PlanarT<S> / SpatialT<S>). Evaluated with S = double they
// give Q; evaluated with forward-mode automatic differentiation (Eigen's
// AutoDiffScalar, seeded with the position increments and the velocities of
// every body) they give the exact Jacobians dQ/dq and dQ/dv, with the
// architecture's conventions: planar increments (dR, dtheta); spatial (dR,
// dpi_bar) with A -> A exp(skew(dpi_bar)), whose first-order part A (I +
// skew(dpi_bar)) is all a first derivative at dpi_bar = 0 needs.
// ---------------------------------------------------------------------------
namespace mbd::force_support {

template <int N>
using AD = Eigen::AutoDiffScalar<Eigen::Matrix<double, N, 1>>;
template <class S>
using V2 = Eigen::Matrix<S, 2, 1>;
template <class S>
using V3 = Eigen::Matrix<S, 3, 1>;
template <class S>
using M2 = Eigen::Matrix<S, 2, 2>;
template <class S>
using M3 = Eigen::Matrix<S, 3, 3>;
// An element's generalized force and its deformation Jacobians, at most two bodies
// (12 velocities): sized at run time but stored in place, so evaluations never allocate.
constexpr int kMaxForceBodies = 2;
template <class S>
using VX = Eigen::Matrix<S, Eigen::Dynamic, 1, 0, 6 * kMaxForceBodies, 1>;
template <class S>
using MX = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6 * kMaxForceBodies>;

inline double value_of(double x) { return x; }
template <class D>
double value_of(const Eigen::AutoDiffScalar<D>& x) { return x.value(); }

// A scalar seeded as the independent variable number `col` (AD) or a plain value (double).
template <class S>
struct Seed {
    static S make(double v, int) { return v; }
};
template <int N>
struct Seed<Eigen::AutoDiffScalar<Eigen::Matrix<double, N, 1>>> {
    static AD<N> make(double v, int col) { return AD<N>(v, N, col); }
};

template <class S>
M3<S> skew_t(const V3<S>& a) {
    M3<S> s;
    s << S(0), -a.z(), a.y(), a.z(), S(0), -a.x(), -a.y(), a.x(), S(0);
    return s;
}
template <class S>
M2<S> rot2(const S& th) {
    using std::cos;
    using std::sin;
    const S c = cos(th), s = sin(th);
    M2<S> a;
    a << c, -s, s, c;
    return a;
}

template <class S>
struct PlanarT {
    V2<S> R, Rdot;
    S theta, omega;
    M2<S> A;
    V2<S> point(const Vec2& u) const { return R + A * u.cast<S>(); }
    V2<S> A_theta_u(const Vec2& u) const { return A * perp(u).cast<S>(); }  // A_theta u = A perp(u) (Eq. 3.28)
    V2<S> point_velocity(const Vec2& u) const { return Rdot + A_theta_u(u) * omega; }
};
template <class S>
struct SpatialT {
    V3<S> R, Rdot, wbar;
    M3<S> A;
    V3<S> point(const Vec3& u) const { return R + A * u.cast<S>(); }
    V3<S> point_velocity(const Vec3& u) const { return Rdot + A * wbar.cross(u.cast<S>()); }
    V3<S> omega() const { return A * wbar; }
};

template <class S>
using PlanarStates = boost::container::static_vector<PlanarT<S>, kMaxForceBodies>;
template <class S>
using SpatialStates = boost::container::static_vector<SpatialT<S>, kMaxForceBodies>;

// The number of bodies of an element (at most kMaxForceBodies).
inline int element_bodies(const BodyStates& b) {
    if (b.size() > kMaxForceBodies) throw std::logic_error("force_support: an element of more than two bodies");
    return b.size();
}
// Seeds every body of the element: body k's position increments are variables C k..,
// its velocities C nb + C k.. (C = 3 planar, 6 spatial); seed(k, q0, v0, out) fills one.
template <class T, int C, class SeedBody>
boost::container::static_vector<T, kMaxForceBodies> seeded_states(const BodyStates& b, const SeedBody& seed) {
    const int nb = element_bodies(b);
    boost::container::static_vector<T, kMaxForceBodies> out(nb);
    for (int k = 0; k < nb; ++k) seed(k, C * k, C * (nb + k), out[k]);
    return out;
}
template <class S>
PlanarStates<S> planar_states(const BodyStates& b) {
    return seeded_states<PlanarT<S>, 3>(b, [&b](int k, int q, int v, PlanarT<S>& o) {
        const PlanarBody& s = b.planar(k);
        o.R << Seed<S>::make(s.R.x(), q), Seed<S>::make(s.R.y(), q + 1);
        o.theta = Seed<S>::make(s.theta, q + 2);
        o.A = rot2(o.theta);
        o.Rdot << Seed<S>::make(s.Rdot.x(), v), Seed<S>::make(s.Rdot.y(), v + 1);
        o.omega = Seed<S>::make(s.omega, v + 2);
    });
}
template <class S>
SpatialStates<S> spatial_states(const BodyStates& b) {
    return seeded_states<SpatialT<S>, 6>(b, [&b](int k, int q, int v, SpatialT<S>& o) {
        const SpatialBody& s = b.spatial(k);
        V3<S> dpi;
        for (int c = 0; c < 3; ++c) {
            o.R[c] = Seed<S>::make(s.R[c], q + c);
            dpi[c] = Seed<S>::make(0.0, q + 3 + c);
            o.Rdot[c] = Seed<S>::make(s.Rdot[c], v + c);
            o.wbar[c] = Seed<S>::make(s.omega_bar[c], v + 3 + c);
        }
        o.A = s.A.cast<S>() * (M3<S>::Identity() + skew_t<S>(dpi));
    });
}

// Q += f(states) for a functor f templated on the state vector type.
template <class F>
void add_value(const BodyStates& b, const F& f, Eigen::Ref<Eigen::VectorXd> Q) {
    if (!b.planar_bodies.empty())
        Q += f(planar_states<double>(b));
    else
        Q += f(spatial_states<double>(b));
}

template <int NV, int NB, class F>
void add_jacobians_impl(const BodyStates& b, const F& f, Eigen::Ref<Eigen::MatrixXd> dQ_dq,
                        Eigen::Ref<Eigen::MatrixXd> dQ_dv) {
    constexpr int n = NV * NB;
    using S = AD<2 * n>;
    VX<S> q;
    if constexpr (NV == 3)
        q = f(planar_states<S>(b));
    else
        q = f(spatial_states<S>(b));
    for (int r = 0; r < n; ++r) {
        const auto& d = q[r].derivatives();
        if (d.size() != 2 * n) continue;  // a constant entry
        for (int c = 0; c < n; ++c) {
            dQ_dq(r, c) += d[c];
            dQ_dv(r, c) += d[n + c];
        }
    }
}
template <int NB, class F>
void add_jacobians(const BodyStates& b, const F& f, Eigen::Ref<Eigen::MatrixXd> dQ_dq,
                   Eigen::Ref<Eigen::MatrixXd> dQ_dv) {
    if (!b.planar_bodies.empty())
        add_jacobians_impl<3, NB>(b, f, dQ_dq, dQ_dv);
    else
        add_jacobians_impl<6, NB>(b, f, dQ_dq, dQ_dv);
}


// Errors name the force and say what to do.
[[noreturn]] inline void fail(const ForceSpec& spec, const std::string& message,
                              const Param* where = nullptr) {
    std::string loc = where ? where->location() : std::string();
    if (loc.empty()) loc = spec.params.location();
    throw InputError(loc, "force '" + spec.name + "': " + message);
}

inline double read_number(const ForceSpec& spec, const std::string& key, const Param& p) {
    return p.as_number(key, "force '" + spec.name + "'");
}
// A number under `key`; without a fallback the key is required.
inline double number(const ForceSpec& spec, const std::string& key, const double* fallback = nullptr) {
    if (!spec.params.has(key)) {
        if (fallback) return *fallback;
        fail(spec, "missing key '" + key + "'");
    }
    return read_number(spec, key, spec.params.at(key));
}
inline double non_negative(const ForceSpec& spec, const std::string& key, const double* fallback = nullptr) {
    const double v = number(spec, key, fallback);
    if (v < 0)
        fail(spec, "'" + key + "' must not be negative, got " + std::to_string(v),
             spec.params.has(key) ? &spec.params.at(key) : nullptr);
    return v;
}
inline double non_negative_or(const ForceSpec& spec, const std::string& key, double fallback) {
    return non_negative(spec, key, &fallback);
}
// A list of exactly `size` numbers (all >= 0 when non_negative).
inline Eigen::VectorXd number_list(const ForceSpec& spec, const std::string& key, int size, bool non_neg) {
    const Param& p = spec.params.at(key);
    if (!p.is_list() || static_cast<int>(p.items.size()) != size)
        fail(spec, "'" + key + "' must be a list of " + std::to_string(size) + " numbers for a " +
                       to_string(spec.dimension) + " model" +
                       (p.is_list() ? ", got " + std::to_string(p.items.size()) : std::string()),
             &p);
    Eigen::VectorXd v(size);
    for (int k = 0; k < size; ++k) {
        v[k] = read_number(spec, key, p.items[k]);
        if (non_neg && v[k] < 0) fail(spec, "'" + key + "' entries must not be negative", &p.items[k]);
    }
    return v;
}
inline void expect_bodies(const ForceSpec& spec, int count, const std::string& what) {
    if (static_cast<int>(spec.bodies.size()) != count)
        fail(spec, "a " + spec.type + " connects " + what + ", got " + std::to_string(spec.bodies.size()) +
                       " bodies");
}
// The optional time function under `key` (a number or {type: ...}); null without the key.
inline std::shared_ptr<const TimeFunction> optional_time_function(const ForceSpec& spec, const std::string& key) {
    if (!spec.params.has(key)) return nullptr;
    return make_time_function(spec.params.at(key), "force '" + spec.name + "' " + key);
}
// Its value at t; 0 without one.
inline double value_or_zero(const std::shared_ptr<const TimeFunction>& f, double t) {
    return f ? f->evaluate(t).f : 0.0;
}
// Components given each as a number or a time function, at t (the rest zero).
using TimeComponents = std::vector<std::shared_ptr<const TimeFunction>>;
inline Vec3 components_at(const TimeComponents& components, double t) {
    Vec3 v = Vec3::Zero();
    for (size_t k = 0; k < components.size(); ++k) v[k] = components[k]->evaluate(t).f;
    return v;
}
// The key 'frame': world (default) or body; true for body (components turn with the body).
inline bool body_frame(const ForceSpec& spec) {
    const std::string frame = spec.params.has("frame") ? spec.params.string("frame") : "world";
    if (frame != "world" && frame != "body")
        fail(spec, "'frame' must be 'world' or 'body', got '" + frame + "'", &spec.params.at("frame"));
    return frame == "body";
}
// The application frame on body k: the marker the core built from the scene's
// points (and axes), or without one the body frame at the mass centre.
inline Marker marker_or_centre(const ForceSpec& spec, int k) {
    return k < static_cast<int>(spec.markers.size()) ? spec.markers[k] : Marker{};
}
// World position of a marker origin at t = 0.
inline Vec3 initial_point(const BodyInfo& body, const Vec3& u_bar) {
    return body.position + body.orientation * u_bar;
}
// The parameters of a spring-damper-actuator (book Secs. 5.4-5.5): stiffness k
// (>= 0, required), damping c (>= 0, default 0) and an optional actuator time
// function under `actuator_key`; its scalar is k x + c xdot + actuator(t).
struct SpringDamperActuator {
    double k = 0.0, c = 0.0;
    std::shared_ptr<const TimeFunction> actuator;

    SpringDamperActuator() = default;
    SpringDamperActuator(const ForceSpec& spec, const std::string& actuator_key)
        : k(non_negative(spec, "stiffness")), c(non_negative_or(spec, "damping", 0.0)),
          actuator(optional_time_function(spec, actuator_key)) {}
    double actuator_at(double t) const { return value_or_zero(actuator, t); }
    // Conservative (potential 1/2 k x^2) without damping and actuator.
    bool conservative() const { return c == 0.0 && !actuator; }
};
// A force element of NB bodies written once: Derived provides `load(t)`, its
// time-dependent input (applied components, an actuator value), and
// `generalized(states, load)`, templated on the scalar type. Q comes from doubles,
// the exact Jacobians dQ/dq and dQ/dv from automatic differentiation of the same
// expression.
template <class Derived, int NB>
class LoadedForce : public Force {
public:
    // bodies: what the element connects, for the error on a wrong body count ("one body").
    LoadedForce(const ForceSpec& spec, const std::string& bodies) : dim_(spec.dimension) {
        expect_bodies(spec, NB, bodies);
    }
    void evaluate(const BodyStates& b, Eigen::Ref<Eigen::VectorXd> Q) const override {
        const auto load = self().load(b.t);
        add_value(b, [&](const auto& s) { return self().generalized(s, load); }, Q);
    }
    bool has_jacobians() const override { return true; }
    void jacobians(const BodyStates& b, Eigen::Ref<Eigen::MatrixXd> dQ_dq,
                   Eigen::Ref<Eigen::MatrixXd> dQ_dv) const override {
        const auto load = self().load(b.t);
        add_jacobians<NB>(b, [&](const auto& s) { return self().generalized(s, load); }, dQ_dq, dQ_dv);
    }

protected:
    Dimension dim_;

private:
    const Derived& self() const { return static_cast<const Derived&>(*this); }
};

// A spring-damper-actuator between two bodies (Secs. 5.4-5.5, 7.7): along a line
// (actuator_key "force") or about an axis ("torque"). Its load is the actuator value
// f_a(t); Derived provides generalized(states, f_a) with sda_.k and sda_.c, and
// reads its attachment points or axes from ends_.
template <class Derived>
class SpringDamperElement : public LoadedForce<Derived, 2> {
public:
    SpringDamperElement(const ForceSpec& spec, const std::string& actuator_key)
        : LoadedForce<Derived, 2>(spec, "two bodies [i, j]"), sda_(spec, actuator_key),
          ends_{marker_or_centre(spec, 0), marker_or_centre(spec, 1)} {}
    double load(double t) const { return sda_.actuator_at(t); }
    bool is_conservative() const override { return sda_.conservative(); }

protected:
    SpringDamperActuator sda_;
    Marker ends_[2];  // the element's frames on bodies i and j (marker_or_centre)
};

}  // namespace mbd::force_support
