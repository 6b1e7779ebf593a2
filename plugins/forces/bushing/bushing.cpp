// Bushing: a linear spring-damper between a marker on body i and a marker on body j.
//
// Deformation delta (marker frames built by the core; they coincide at t = 0):
//   planar  (3): d = A_mi^T (r_Pj - r_Pi) (origin of marker j relative to marker i, in marker i
//                axes), and the relative angle theta_j + alpha_j - theta_i - alpha_i (not wrapped);
//   spatial (6): d as above (3-vectors), and the rotation vector phi = log(A_mi^T A_mj) of the
//                relative rotation of the marker frames (exact log map, no small-angle
//                approximation; reliable up to rotations of about 170 degrees, the log map is
//                singular at 180).
// Generalized elastic/damping force on delta: F = -(K delta + C deltadot) (K, C diagonal), i.e.
// the force on j is -(K delta + C deltadot) in marker i axes and body i carries the reaction.
// Generalized forces by virtual work (book Eq. 5.49): Q = J^T F with J = d delta / dq
// (deltadot = J v). Spatial rotation rows: d phi = J_r^{-1}(phi) Abar_j^T dpi_j - J_l^{-1}(phi) Abar_i^T dpi_i.
// Potential 1/2 delta^T K delta, exact for both (Q = -dV/dq when C = 0).
// Keys: stiffness: [3 numbers (planar: x, y, angle) or 6 (spatial: x, y, z, rx, ry, rz)], all >= 0;
//       damping: same size (default zeros).
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

template <class D>
Eigen::Matrix<double, D::RowsAtCompileTime, D::ColsAtCompileTime> values_of(const Eigen::MatrixBase<D>& m) {
    Eigen::Matrix<double, D::RowsAtCompileTime, D::ColsAtCompileTime> out(m.rows(), m.cols());
    for (int r = 0; r < m.rows(); ++r)
        for (int c = 0; c < m.cols(); ++c) out(r, c) = value_of(m(r, c));
    return out;
}

// Rotation vector of a rotation matrix (log map).
template <class S>
V3<S> log_so3(const M3<S>& R) {
    using std::atan2;
    using std::sqrt;
    V3<S> w;  // sin(theta) n
    w << (R(2, 1) - R(1, 2)) / 2, (R(0, 2) - R(2, 0)) / 2, (R(1, 0) - R(0, 1)) / 2;
    const S s2 = w.squaredNorm();
    const S c = (R.trace() - 1.0) / 2.0;
    if (value_of(c) > 0 && value_of(s2) < 1e-16) return w * (1.0 + s2 / 6.0 + 3.0 * s2 * s2 / 40.0);
    if (value_of(s2) > 1e-24) {
        const S s = sqrt(s2);
        const S theta = atan2(s, c);
        return w * (theta / s);
    }
    // theta = pi: value from the symmetric part (no derivatives there)
    const Eigen::AngleAxisd aa(Mat3(values_of(R)));
    return (aa.angle() * aa.axis()).cast<S>();
}

// J_r^{-1}(phi) (sign = +1) or J_l^{-1}(phi) (sign = -1) = I +- 1/2 phi~ + beta phi~^2.
template <class S>
M3<S> inverse_jacobian_so3(const V3<S>& phi, double sign) {
    using std::cos;
    using std::sin;
    using std::sqrt;
    const S t2 = phi.squaredNorm();
    S beta;
    if (value_of(t2) < 1e-6) {
        beta = 1.0 / 12.0 + t2 / 720.0 + t2 * t2 / 30240.0;
    } else {
        const S t = sqrt(t2);
        beta = 1.0 / t2 - cos(t / 2.0) / (2.0 * t * sin(t / 2.0));
    }
    const M3<S> P = skew_t<S>(phi);
    return M3<S>::Identity() + P * S(0.5 * sign) + P * P * beta;
}

class Bushing final : public Force {
public:
    explicit Bushing(const ForceSpec& spec) : dim_(spec.dimension) {
        expect_bodies(spec, 2, "two bodies [i, j]");
        if (spec.markers.size() != 2)
            fail(spec, "a bushing needs a marker on each body (give 'point', and 'axis' for its frame)");
        for (int k = 0; k < 2; ++k) marker_[k] = spec.markers[k];
        const int n = dim_ == Dimension::Planar ? 3 : 6;
        if (!spec.params.has("stiffness"))
            fail(spec, "missing key 'stiffness': a list of " + std::to_string(n) + " numbers" +
                           (n == 3 ? " [kx, ky, k_angle]" : " [kx, ky, kz, krx, kry, krz]"));
        K_ = number_list(spec, "stiffness", n, true);
        C_ = spec.params.has("damping") ? number_list(spec, "damping", n, true) : Eigen::VectorXd::Zero(n);
    }

    void evaluate(const BodyStates& b, Eigen::Ref<Eigen::VectorXd> Q) const override {
        add_value(b, [&](const auto& s) { return this->generalized(s); }, Q);
    }
    bool has_jacobians() const override { return true; }
    void jacobians(const BodyStates& b, Eigen::Ref<Eigen::MatrixXd> dQ_dq,
                   Eigen::Ref<Eigen::MatrixXd> dQ_dv) const override {
        add_jacobians<2>(b, [&](const auto& s) { return this->generalized(s); }, dQ_dq, dQ_dv);
    }
    double potential_energy(const BodyStates& b) const override {
        Eigen::VectorXd delta;
        Eigen::MatrixXd J;
        if (!b.planar_bodies.empty())
            deformation(planar_states<double>(b), delta, J);
        else
            deformation(spatial_states<double>(b), delta, J);
        return 0.5 * delta.dot(K_.cwiseProduct(delta));
    }
    bool is_conservative() const override { return C_.isZero(0.0); }

    template <class S>
    void deformation(const std::vector<PlanarT<S>>& s, VX<S>& delta, Eigen::Matrix<S, -1, -1>& J) const {
        const Vec2 ui = marker_[0].u_bar2(), uj = marker_[1].u_bar2();
        const M2<S> Mi = s[0].A * planar_rotation(marker_[0].angle).cast<S>();
        const V2<S> r = s[1].point(uj) - s[0].point(ui);
        const V2<S> d = Mi.transpose() * r;
        delta.resize(3);
        delta << d, s[1].theta + marker_[1].angle - s[0].theta - marker_[0].angle;
        J = Eigen::Matrix<S, -1, -1>::Zero(3, 6);
        J.template block<2, 2>(0, 0) = -Mi.transpose();
        V2<S> Std;  // S^T d, S = [[0,-1],[1,0]]: derivative of A_mi^T with theta_i
        Std << d.y(), -d.x();
        J.template block<2, 1>(0, 2) = -Mi.transpose() * s[0].A_theta_u(ui) + Std;
        J.template block<2, 2>(0, 3) = Mi.transpose();
        J.template block<2, 1>(0, 5) = Mi.transpose() * s[1].A_theta_u(uj);
        J(2, 2) = S(-1);
        J(2, 5) = S(1);
    }
    template <class S>
    void deformation(const std::vector<SpatialT<S>>& s, VX<S>& delta, Eigen::Matrix<S, -1, -1>& J) const {
        const Vec3 ui = marker_[0].u_bar, uj = marker_[1].u_bar;
        const M3<S> Abi = marker_[0].A_bar.cast<S>(), Abj = marker_[1].A_bar.cast<S>();
        const M3<S> Mi = s[0].A * Abi, Mj = s[1].A * Abj;
        const V3<S> r = s[1].point(uj) - s[0].point(ui);
        const V3<S> d = Mi.transpose() * r;
        const V3<S> phi = log_so3<S>(Mi.transpose() * Mj);
        delta.resize(6);
        delta << d, phi;
        J = Eigen::Matrix<S, -1, -1>::Zero(6, 12);
        J.template block<3, 3>(0, 0) = -Mi.transpose();
        J.template block<3, 3>(0, 3) = Abi.transpose() * (skew_t<S>(s[0].A.transpose() * r) +
                                                          skew_t<S>(ui.cast<S>()));
        J.template block<3, 3>(0, 6) = Mi.transpose();
        J.template block<3, 3>(0, 9) = -Mi.transpose() * s[1].A * skew_t<S>(uj.cast<S>());
        J.template block<3, 3>(3, 3) = -inverse_jacobian_so3<S>(phi, -1.0) * Abi.transpose();
        J.template block<3, 3>(3, 9) = inverse_jacobian_so3<S>(phi, 1.0) * Abj.transpose();
    }

    template <class State>
    auto generalized(const std::vector<State>& s) const {
        using S = std::decay_t<decltype(s[0].R[0])>;
        VX<S> delta;
        Eigen::Matrix<S, -1, -1> J;
        deformation(s, delta, J);
        VX<S> v(J.cols());
        const int nv = static_cast<int>(J.cols()) / 2;
        for (int k = 0; k < 2; ++k) {
            if constexpr (std::is_same_v<State, PlanarT<S>>)
                v.segment(k * nv, nv) << s[k].Rdot, s[k].omega;
            else
                v.segment(k * nv, nv) << s[k].Rdot, s[k].wbar;
        }
        const VX<S> rate = J * v;
        VX<S> F(delta.size());
        for (int m = 0; m < delta.size(); ++m) F[m] = -(K_[m] * delta[m] + C_[m] * rate[m]);
        return VX<S>(J.transpose() * F);  // virtual work, Eq. 5.49
    }

private:
    Dimension dim_;
    Marker marker_[2];
    Eigen::VectorXd K_, C_;
};

std::unique_ptr<Force> make_bushing(const ForceSpec& spec) { return std::make_unique<Bushing>(spec); }

}  // namespace

MBD_FORCE_PLUGIN(bushing, make_bushing)
