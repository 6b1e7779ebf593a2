// Gravity on every body of the force (the core gives all bodies but the ground),
// book Eqs. 5.58-5.60: with the body reference at the mass centre the work
// delta W = m g . delta R gives Q_R = m g and no moment (planar Q_theta = 0,
// spatial Q_pi_bar = 0). g = ForceSpec::gravity (planar uses x, y).
// V = -sum m g . R; conservative; the Jacobians are zero. Reads no keys.
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

class Gravity final : public Force {
public:
    explicit Gravity(const ForceSpec& spec) : dim_(spec.dimension), g_(spec.gravity) {
        if (dim_ == Dimension::Planar) g_.z() = 0.0;
        for (const BodyInfo& b : spec.bodies) {
            if (!(b.mass >= 0)) fail(spec, "body '" + b.name + "' has a negative mass");
            mass_.push_back(b.ground ? 0.0 : b.mass);
        }
    }
    void evaluate(const BodyStates& b, Eigen::Ref<Eigen::VectorXd> Q) const override {
        const int nv = velocities_per_body(dim_), nd = dim_ == Dimension::Planar ? 2 : 3;
        for (int k = 0; k < b.size() && k < static_cast<int>(mass_.size()); ++k)
            Q.segment(k * nv, nd) += mass_[k] * g_.head(nd);  // (5.58-5.60)
    }
    bool has_jacobians() const override { return true; }
    void jacobians(const BodyStates&, Eigen::Ref<Eigen::MatrixXd>, Eigen::Ref<Eigen::MatrixXd>) const override {}
    double potential_energy(const BodyStates& b) const override {
        double v = 0.0;
        for (int k = 0; k < b.size() && k < static_cast<int>(mass_.size()); ++k) {
            if (dim_ == Dimension::Planar)
                v -= mass_[k] * g_.head<2>().dot(b.planar(k).R);
            else
                v -= mass_[k] * g_.dot(b.spatial(k).R);
        }
        return v;
    }
    bool is_conservative() const override { return true; }

private:
    Dimension dim_;
    Vec3 g_;
    std::vector<double> mass_;
};

std::unique_ptr<Force> make_gravity(const ForceSpec& spec) { return std::make_unique<Gravity>(spec); }

}  // namespace

MBD_FORCE_PLUGIN(gravity, make_gravity)

// The keys of a scene entry (mbd/sdk/plugin_keys.hpp): `mbd plugin check` builds its test scene
// from the examples; docs/scene-format.md is checked against them (tests/test_plugin_keys.cpp).
namespace {
const mbd::PluginKey gravity_keys[] = {
    {}};
}  // namespace

MBD_FORCE_KEYS(gravity, "m g on every body, from the top-level `gravity`", mbd::kEveryBody, mbd::kPlanarAndSpatial, gravity_keys)
