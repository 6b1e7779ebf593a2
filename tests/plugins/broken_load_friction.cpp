// A deliberately broken friction element for `mbd plugin check`: a viscous-like pin friction
// moment -c(N) w about the plane normal on each body (planar), c(N) = 0.01 (1 + N^2): its
// moment is not affine in the load N, which Force::evaluate_at_load must be (the reaction-load
// solver extrapolates from Q(1) - Q(0)). Everything else is consistent (no Jacobians, so
// only the load check applies). A fixture, not a test: it holds no assertions itself;
// tests/test_plugin_check.cpp (PluginCheck) runs `mbd plugin check` on it and asserts the FAIL
// line of exactly that check.
#include <mbd/sdk/plugin.hpp>

namespace {

class BrokenLoadFriction : public mbd::Force {
public:
    explicit BrokenLoadFriction(double load) : load_(load) {}
    void evaluate(const mbd::BodyStates& bodies, Eigen::Ref<Eigen::VectorXd> Q) const override {
        evaluate_at_load(bodies, load_, Q);
    }
    void evaluate_at_load(const mbd::BodyStates& bodies, double load, Eigen::Ref<Eigen::VectorXd> Q) const override {
        const double c = 0.01 * (1.0 + load * load);  // broken: quadratic in the load
        for (int k = 0; k < bodies.size(); ++k) Q[3 * k + 2] -= c * bodies.planar(k).omega;
    }
    bool is_friction() const override { return true; }

private:
    double load_;
};

std::unique_ptr<mbd::Force> make_broken_load_friction(const mbd::ForceSpec& spec) {
    if (spec.dimension != mbd::Dimension::Planar) spec.params.fail("broken_load_friction is planar only");
    return std::make_unique<BrokenLoadFriction>(spec.params.number("normal_force", 1.0));
}

}  // namespace

MBD_FORCE_PLUGIN(broken_load_friction, make_broken_load_friction)
