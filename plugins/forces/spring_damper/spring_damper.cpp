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

class SpringDamper final : public Force {
public:
    explicit SpringDamper(const ForceSpec& spec) : dim_(spec.dimension) {
        expect_bodies(spec, 2, "two bodies [i, j]");
        for (int k = 0; k < 2; ++k)
            u_[k] = k < static_cast<int>(spec.markers.size()) ? spec.markers[k].u_bar : Vec3::Zero();
        if (dim_ == Dimension::Planar) u_[0].z() = u_[1].z() = 0.0;
        k_ = non_negative(spec, "stiffness");
        const double zero = 0.0;
        c_ = non_negative(spec, "damping", &zero);
        if (spec.params.has("force")) actuator_ = make_time_function(spec.params.at("force"), "force '" + spec.name + "' force");
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

    void evaluate(const BodyStates& b, Eigen::Ref<Eigen::VectorXd> Q) const override {
        const double fa = actuator_ ? actuator_->evaluate(b.t).f : 0.0;
        add_value(b, [&](const auto& s) { return this->generalized(s, fa); }, Q);
    }
    bool has_jacobians() const override { return true; }
    void jacobians(const BodyStates& b, Eigen::Ref<Eigen::MatrixXd> dQ_dq,
                   Eigen::Ref<Eigen::MatrixXd> dQ_dv) const override {
        const double fa = actuator_ ? actuator_->evaluate(b.t).f : 0.0;
        add_jacobians<2>(b, [&](const auto& s) { return this->generalized(s, fa); }, dQ_dq, dQ_dv);
    }
    double potential_energy(const BodyStates& b) const override {
        double l;
        if (!b.planar_bodies.empty())
            l = (b.planar(0).point(u_[0].head<2>()) - b.planar(1).point(u_[1].head<2>())).norm();
        else
            l = (b.spatial(0).point(u_[0]) - b.spatial(1).point(u_[1])).norm();
        return 0.5 * k_ * (l - l0_) * (l - l0_);
    }
    bool is_conservative() const override { return c_ == 0.0 && !actuator_; }

    template <class S>
    VX<S> generalized(const std::vector<PlanarT<S>>& s, double fa) const {
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
        const S f = k_ * (l - l0_) + c_ * ldot + fa;            // (5.61)
        Q.template segment<2>(0) = -f * lhat;                   // (5.70a)
        Q[2] = -f * s[0].A_theta_u(ui).dot(lhat);
        Q.template segment<2>(3) = f * lhat;                    // (5.70b)
        Q[5] = f * s[1].A_theta_u(uj).dot(lhat);
        return Q;
    }
    template <class S>
    VX<S> generalized(const std::vector<SpatialT<S>>& s, double fa) const {
        using std::sqrt;
        const V3<S> r = s[0].point(u_[0]) - s[1].point(u_[1]);
        VX<S> Q = VX<S>::Zero(12);
        const S l2 = r.squaredNorm();
        if (value_of(l2) < 1e-24) return Q;
        const S l = sqrt(l2);
        const V3<S> lhat = r / l;
        const V3<S> rdot = s[0].point_velocity(u_[0]) - s[1].point_velocity(u_[1]);
        const S ldot = lhat.dot(rdot);
        const S f = k_ * (l - l0_) + c_ * ldot + fa;                     // (7.116)
        Q.template segment<3>(0) = -f * lhat;                            // (7.121-7.124), moments
        Q.template segment<3>(3) = -f * u_[0].cast<S>().cross(s[0].A.transpose() * lhat);  // in body axes
        Q.template segment<3>(6) = f * lhat;
        Q.template segment<3>(9) = f * u_[1].cast<S>().cross(s[1].A.transpose() * lhat);
        return Q;
    }

private:
    Dimension dim_;
    Vec3 u_[2];
    double k_ = 0, c_ = 0, l0_ = 0;
    std::shared_ptr<const TimeFunction> actuator_;
};

std::unique_ptr<Force> make_spring_damper(const ForceSpec& spec) { return std::make_unique<SpringDamper>(spec); }

}  // namespace

MBD_FORCE_PLUGIN(spring_damper, make_spring_damper)
