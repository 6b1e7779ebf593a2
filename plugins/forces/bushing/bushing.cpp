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
        VX<double> delta;
        MX<double> J;
        if (!b.planar_bodies.empty())
            deformation(planar_states<double>(b), delta, J);
        else
            deformation(spatial_states<double>(b), delta, J);
        return 0.5 * delta.dot(K_.cwiseProduct(delta));
    }
    bool is_conservative() const override { return C_.isZero(0.0); }

    template <class S>
    void deformation(const PlanarStates<S>& s, VX<S>& delta, MX<S>& J) const {
        const Vec2 ui = marker_[0].u_bar2(), uj = marker_[1].u_bar2();
        const M2<S> Mi = s[0].A * planar_rotation(marker_[0].angle).cast<S>();
        const V2<S> r = s[1].point(uj) - s[0].point(ui);
        const V2<S> d = Mi.transpose() * r;
        delta.resize(3);
        delta << d, s[1].theta + marker_[1].angle - s[0].theta - marker_[0].angle;
        J = MX<S>::Zero(3, 6);
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
    void deformation(const SpatialStates<S>& s, VX<S>& delta, MX<S>& J) const {
        const Vec3 ui = marker_[0].u_bar, uj = marker_[1].u_bar;
        const M3<S> Abi = marker_[0].A_bar.cast<S>(), Abj = marker_[1].A_bar.cast<S>();
        const M3<S> Mi = s[0].A * Abi, Mj = s[1].A * Abj;
        const V3<S> r = s[1].point(uj) - s[0].point(ui);
        const V3<S> d = Mi.transpose() * r;
        const V3<S> phi = log_so3<S>(Mi.transpose() * Mj);
        delta.resize(6);
        delta << d, phi;
        J = MX<S>::Zero(6, 12);
        J.template block<3, 3>(0, 0) = -Mi.transpose();
        J.template block<3, 3>(0, 3) = Abi.transpose() * (skew_t<S>(s[0].A.transpose() * r) +
                                                          skew_t<S>(ui.cast<S>()));
        J.template block<3, 3>(0, 6) = Mi.transpose();
        J.template block<3, 3>(0, 9) = -Mi.transpose() * s[1].A * skew_t<S>(uj.cast<S>());
        J.template block<3, 3>(3, 3) = -inverse_jacobian_so3<S>(phi, -1.0) * Abi.transpose();
        J.template block<3, 3>(3, 9) = inverse_jacobian_so3<S>(phi, 1.0) * Abj.transpose();
    }

    template <class States>
    auto generalized(const States& s) const {
        using State = typename States::value_type;
        using S = std::decay_t<decltype(s[0].R[0])>;
        VX<S> delta;
        MX<S> J;
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

// The keys of a scene entry (mbd/sdk/plugin_keys.hpp): `mbd plugin check` builds its test scene
// from the examples; docs/scene-format.md is checked against them (tests/test_plugin_keys.cpp).
namespace {
const mbd::PluginKey bushing_keys[] = {
    {"stiffness", "planar [x, y, angle], spatial [x, y, z, rx, ry, rz], each >= 0", nullptr, "[2000, 1500, 50]", "[2000, 1500, 1000, 50, 40, 30]"},
    {"damping", "as stiffness, each >= 0", "zeros", "[20, 15, 0.5]", "[20, 15, 10, 0.5, 0.4, 0.3]"},
    {}};
}  // namespace

MBD_FORCE_KEYS(bushing, "a linear bushing: stiffness and damping per axis of marker i", mbd::kTwoBodies, mbd::kPlanarAndSpatial, bushing_keys)
