// A force applied at a point of one body (book Eqs. 5.45-5.46; spatial 7.111-7.115).
//   planar:  Q = [F; (A u_bar) x F]  (z component; = u_bar^T A_theta^T F)
//   spatial: Q_R = F (world), Q_pi_bar = u_bar x (A^T F)  (moment in body axes)
// Keys: force: a list of 2 (planar) or 3 (spatial) components, each a number or a
// time function; frame: world (default) or body (components in body axes, turning with
// the body). The point is the marker the core builds from 'point' (body frame); without
// a marker, the mass centre. Not conservative; exact Jacobians (non-zero for frame: body
// and for the moment of a world-fixed force as the body turns).
#include <mbd/sdk/force_support.hpp>
#include <mbd/sdk/plugin.hpp>
#include <mbd/sdk/time_function.hpp>

#include <cmath>
#include <memory>
#include <string>
#include <vector>
namespace {

using namespace mbd;
using namespace mbd::force_support;

class PointForce final : public Force {
public:
    explicit PointForce(const ForceSpec& spec) : dim_(spec.dimension) {
        expect_bodies(spec, 1, "one body");
        u_ = spec.markers.empty() ? Vec3::Zero() : spec.markers[0].u_bar;
        const int n = dim_ == Dimension::Planar ? 2 : 3;
        if (dim_ == Dimension::Planar) u_.z() = 0.0;
        if (!spec.params.has("force")) fail(spec, "missing key 'force' (e.g. force: [0, -9.81] (planar) or [0, 0, -9.81] (spatial))");
        const Param& f = spec.params.at("force");
        if (!f.is_list() || static_cast<int>(f.items.size()) != n)
            fail(spec, "'force' must be a list of " + std::to_string(n) + " components for a " +
                           to_string(dim_) + " model (each a number or a time function)",
                 &f);
        for (int k = 0; k < n; ++k)
            components_.push_back(make_time_function(
                f.items[k], "force '" + spec.name + "' force[" + std::to_string(k) + "]"));
        const std::string frame = spec.params.has("frame") ? spec.params.string("frame") : "world";
        if (frame != "world" && frame != "body")
            fail(spec, "'frame' must be 'world' or 'body', got '" + frame + "'", &spec.params.at("frame"));
        body_frame_ = frame == "body";
    }

    void evaluate(const BodyStates& b, Eigen::Ref<Eigen::VectorXd> Q) const override {
        const Vec3 F = components(b.t);
        add_value(b, [&](const auto& s) { return this->generalized(s, F); }, Q);
    }
    bool has_jacobians() const override { return true; }
    void jacobians(const BodyStates& b, Eigen::Ref<Eigen::MatrixXd> dQ_dq,
                   Eigen::Ref<Eigen::MatrixXd> dQ_dv) const override {
        const Vec3 F = components(b.t);
        add_jacobians<1>(b, [&](const auto& s) { return this->generalized(s, F); }, dQ_dq, dQ_dv);
    }

    Vec3 components(double t) const {
        Vec3 F = Vec3::Zero();
        for (size_t k = 0; k < components_.size(); ++k) F[k] = components_[k]->evaluate(t).f;
        return F;
    }
    template <class S>
    VX<S> generalized(const PlanarStates<S>& s, const Vec3& F) const {
        const V2<S> Fw = body_frame_ ? V2<S>(s[0].A * F.head<2>().cast<S>()) : V2<S>(F.head<2>().cast<S>());
        VX<S> Q(3);
        Q << Fw, s[0].A_theta_u(u_.head<2>()).dot(Fw);  // (5.45): u_bar^T A_theta^T F = (A u_bar) x F
        return Q;
    }
    template <class S>
    VX<S> generalized(const SpatialStates<S>& s, const Vec3& F) const {
        const V3<S> Fw = body_frame_ ? V3<S>(s[0].A * F.cast<S>()) : V3<S>(F.cast<S>());
        const V3<S> Fb = body_frame_ ? V3<S>(F.cast<S>()) : V3<S>(s[0].A.transpose() * Fw);
        VX<S> Q(6);
        Q << Fw, u_.cast<S>().cross(Fb);  // (7.111-7.115) with Gbar^T -> body-axis moment
        return Q;
    }

private:
    Dimension dim_;
    Vec3 u_;
    bool body_frame_ = false;
    std::vector<std::shared_ptr<const TimeFunction>> components_;
};

std::unique_ptr<Force> make_point_force(const ForceSpec& spec) { return std::make_unique<PointForce>(spec); }

}  // namespace

MBD_FORCE_PLUGIN(point_force, make_point_force)
