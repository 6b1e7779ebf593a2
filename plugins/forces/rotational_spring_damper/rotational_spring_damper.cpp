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
#include <mbd/sdk/plugin.hpp>
#include <mbd/sdk/time_function.hpp>

#include <unsupported/Eigen/AutoDiff>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

// ---------------------------------------------------------------------------
// Helpers shared by the force plugins. Each plugin is one self-contained source
// file, so this block is repeated in every plugins/forces/<type>/<type>.cpp.
//
// Generalized forces are written once, as templates on the scalar type S, of
// per-body states (PlanarT<S> / SpatialT<S>). Evaluated with S = double they
// give Q; evaluated with forward-mode automatic differentiation (Eigen's
// AutoDiffScalar, seeded with the position increments and the velocities of
// every body) they give the exact Jacobians dQ/dq and dQ/dv, with the
// architecture's conventions: planar increments (dR, dtheta); spatial (dR,
// dpi_bar) with A -> A exp(skew(dpi_bar)), whose first-order part A (I +
// skew(dpi_bar)) is all a first derivative at dpi_bar = 0 needs.
// ---------------------------------------------------------------------------
namespace {

using namespace mbd;

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
template <class S>
using VX = Eigen::Matrix<S, Eigen::Dynamic, 1>;

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

// States of all bodies; body k's position increments are variables 3k.. (planar) or
// 6k.. (spatial), its velocities follow after all the increments.
template <class S>
std::vector<PlanarT<S>> planar_states(const BodyStates& b) {
    const int nb = b.size(), n = 3 * nb;
    std::vector<PlanarT<S>> out(nb);
    for (int k = 0; k < nb; ++k) {
        const PlanarBody& s = b.planar(k);
        PlanarT<S>& o = out[k];
        o.R << Seed<S>::make(s.R.x(), 3 * k), Seed<S>::make(s.R.y(), 3 * k + 1);
        o.theta = Seed<S>::make(s.theta, 3 * k + 2);
        o.A = rot2(o.theta);
        o.Rdot << Seed<S>::make(s.Rdot.x(), n + 3 * k), Seed<S>::make(s.Rdot.y(), n + 3 * k + 1);
        o.omega = Seed<S>::make(s.omega, n + 3 * k + 2);
    }
    return out;
}
template <class S>
std::vector<SpatialT<S>> spatial_states(const BodyStates& b) {
    const int nb = b.size(), n = 6 * nb;
    std::vector<SpatialT<S>> out(nb);
    for (int k = 0; k < nb; ++k) {
        const SpatialBody& s = b.spatial(k);
        SpatialT<S>& o = out[k];
        V3<S> dpi;
        for (int c = 0; c < 3; ++c) {
            o.R[c] = Seed<S>::make(s.R[c], 6 * k + c);
            dpi[c] = Seed<S>::make(0.0, 6 * k + 3 + c);
            o.Rdot[c] = Seed<S>::make(s.Rdot[c], n + 6 * k + c);
            o.wbar[c] = Seed<S>::make(s.omega_bar[c], n + 6 * k + 3 + c);
        }
        o.A = s.A.cast<S>() * (M3<S>::Identity() + skew_t<S>(dpi));
    }
    return out;
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
    if (p.is_scalar()) {
        try {
            size_t used = 0;
            const double v = std::stod(p.text, &used);
            if (used == p.text.size() && std::isfinite(v)) return v;
        } catch (const std::exception&) {
        }
    }
    fail(spec, "'" + key + "' must be a number" + (p.is_scalar() ? ", got '" + p.text + "'" : std::string()),
         &p);
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
// World position of a marker origin at t = 0.
inline Vec3 initial_point(const BodyInfo& body, const Vec3& u_bar) {
    return body.position + body.orientation * u_bar;
}

}  // namespace
// ---------------------------------------------------------------------------
namespace {

class RotationalSpringDamper final : public Force {
public:
    explicit RotationalSpringDamper(const ForceSpec& spec) : dim_(spec.dimension) {
        expect_bodies(spec, 2, "two bodies [i, j]");
        for (int k = 0; k < 2; ++k)
            frame_[k] = k < static_cast<int>(spec.markers.size()) ? spec.markers[k].A_bar : Mat3::Identity();
        k_ = non_negative(spec, "stiffness");
        const double zero = 0.0;
        c_ = non_negative(spec, "damping", &zero);
        if (spec.params.has("torque"))
            actuator_ = make_time_function(spec.params.at("torque"), "force '" + spec.name + "' torque");
        double initial;
        if (dim_ == Dimension::Planar) {
            initial = spec.bodies[1].angle - spec.bodies[0].angle;
        } else {
            const Mat3 ai = spec.bodies[0].orientation * frame_[0], aj = spec.bodies[1].orientation * frame_[1];
            initial = std::atan2(ai.col(1).dot(aj.col(0)), ai.col(0).dot(aj.col(0)));
        }
        rest_ = number(spec, "rest_angle", &initial);
    }

    void evaluate(const BodyStates& b, Eigen::Ref<Eigen::VectorXd> Q) const override {
        const double ta = actuator_ ? actuator_->evaluate(b.t).f : 0.0;
        add_value(b, [&](const auto& s) { return this->generalized(s, ta); }, Q);
    }
    bool has_jacobians() const override { return true; }
    void jacobians(const BodyStates& b, Eigen::Ref<Eigen::MatrixXd> dQ_dq,
                   Eigen::Ref<Eigen::MatrixXd> dQ_dv) const override {
        const double ta = actuator_ ? actuator_->evaluate(b.t).f : 0.0;
        add_jacobians<2>(b, [&](const auto& s) { return this->generalized(s, ta); }, dQ_dq, dQ_dv);
    }
    double potential_energy(const BodyStates& b) const override {
        double angle;
        if (!b.planar_bodies.empty()) {
            angle = value_of(planar_angle(planar_states<double>(b)));
        } else {
            V3<double> h;
            angle = spatial_angle(spatial_states<double>(b), h);
        }
        return 0.5 * k_ * angle * angle;
    }
    bool is_conservative() const override { return c_ == 0.0 && !actuator_; }

    template <class S>
    S planar_angle(const std::vector<PlanarT<S>>& s) const {
        return s[1].theta - s[0].theta - rest_;
    }
    template <class S>
    VX<S> generalized(const std::vector<PlanarT<S>>& s, double ta) const {
        const S T = k_ * planar_angle(s) + c_ * (s[1].omega - s[0].omega) + ta;  // (5.73), c_r thetadot
        VX<S> Q = VX<S>::Zero(6);
        Q[2] = T;
        Q[5] = -T;
        return Q;
    }

    // Spatial relative angle about z_i and the direction h of its gradient (world axes).
    template <class S>
    S spatial_angle(const std::vector<SpatialT<S>>& s, V3<S>& h) const {
        using std::atan2;
        const M3<S> ai = s[0].A * frame_[0].cast<S>(), aj = s[1].A * frame_[1].cast<S>();
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
    VX<S> generalized(const std::vector<SpatialT<S>>& s, double ta) const {
        V3<S> h;
        const S angle = spatial_angle(s, h);
        const S rate = h.dot(s[1].omega() - s[0].omega());
        const S T = k_ * angle + c_ * rate + ta;  // (7.129-7.132) with a rest angle
        VX<S> Q = VX<S>::Zero(12);
        Q.template segment<3>(3) = (s[0].A.transpose() * h) * T;
        Q.template segment<3>(9) = -(s[1].A.transpose() * h) * T;
        return Q;
    }

private:
    Dimension dim_;
    Mat3 frame_[2];
    double k_ = 0, c_ = 0, rest_ = 0;
    std::shared_ptr<const TimeFunction> actuator_;
};

std::unique_ptr<Force> make_rotational_spring_damper(const ForceSpec& spec) {
    return std::make_unique<RotationalSpringDamper>(spec);
}

}  // namespace

MBD_FORCE_PLUGIN(rotational_spring_damper, make_rotational_spring_damper)
