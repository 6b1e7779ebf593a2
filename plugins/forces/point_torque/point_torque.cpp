// A pure moment on one body (book Eq. 5.46: Q_theta = M; spatial Eq. 7.115: moments
// enter as Gbar^T M_bar, here directly as body-axis moments).
//   planar:  Q_theta = T(t)   (frame makes no difference in the plane)
//   spatial: frame world: Q_pi_bar = A^T T_world;  frame body: Q_pi_bar = T_bar
// Keys: torque: planar one component (a number, a time function, or a list of one);
// spatial a list of 3 components (each a number or a time function);
// frame: world (default) or body. Exact Jacobians.
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

class PointTorque final : public LoadedForce<PointTorque, 1> {
public:
    explicit PointTorque(const ForceSpec& spec) : LoadedForce(spec, "one body") {
        if (!spec.params.has("torque")) fail(spec, "missing key 'torque' (e.g. torque: 2.5 (planar) or [0, 0, 2.5] (spatial))");
        const Param& p = spec.params.at("torque");
        const std::string what = "force '" + spec.name + "' torque";
        if (dim_ == Dimension::Planar) {
            if (p.is_list()) {
                if (p.items.size() != 1)
                    fail(spec, "a planar 'torque' has one component (a number or a time function), got " +
                                   std::to_string(p.items.size()),
                         &p);
                components_.push_back(make_time_function(p.items[0], what));
            } else {
                components_.push_back(make_time_function(p, what));
            }
        } else {
            if (!p.is_list() || p.items.size() != 3)
                fail(spec, "a spatial 'torque' must be a list of 3 components (each a number or a time function)",
                     &p);
            for (int k = 0; k < 3; ++k)
                components_.push_back(make_time_function(p.items[k], what + "[" + std::to_string(k) + "]"));
        }
        body_frame_ = body_frame(spec);
    }

    // the applied torque T(t) (planar: its one component first)
    Vec3 load(double t) const { return components_at(components_, t); }
    template <class S>
    VX<S> generalized(const PlanarStates<S>&, const Vec3& T) const {
        VX<S> Q = VX<S>::Zero(3);
        Q[2] = S(T[0]);
        return Q;
    }
    template <class S>
    VX<S> generalized(const SpatialStates<S>& s, const Vec3& T) const {
        VX<S> Q = VX<S>::Zero(6);
        if (body_frame_)
            Q.template segment<3>(3) = T.cast<S>();
        else
            Q.template segment<3>(3) = s[0].A.transpose() * T.cast<S>();
        return Q;
    }

private:
    bool body_frame_ = false;
    TimeComponents components_;
};

std::unique_ptr<Force> make_point_torque(const ForceSpec& spec) { return std::make_unique<PointTorque>(spec); }

}  // namespace

MBD_FORCE_PLUGIN(point_torque, make_point_torque)

// The keys of a scene entry (mbd/sdk/plugin_keys.hpp): `mbd plugin check` builds its test scene
// from the examples; docs/scene-format.md is checked against them (tests/test_plugin_keys.cpp).
namespace {
const mbd::PluginKey point_torque_keys[] = {
    {"torque", "planar: one component; spatial: 3; each a number or a time function", nullptr, "0.5", "[0.5, -1, 0.2]"},
    {"frame", "world or body (components in body axes)", "world", "body", nullptr, true},
    {}};
}  // namespace

MBD_FORCE_KEYS(point_torque, "a torque on one body", mbd::kOneBody, mbd::kPlanarAndSpatial, point_torque_keys)
