// A deliberately broken velocity-level joint for `mbd plugin check`: a spatial skate (knife
// edge), the velocity of the marker origin P on body j along the marker's y axis is zero,
// y . (Rdot_j + omega_j x u_P) = 0 (one nonholonomic row, no holonomic row). Its A is right;
// its gamma leaves out the velocity-quadratic terms (the right one is
// -(ydot . V_P + y . (omega x (omega x u_P)))). A fixture, not a test: it holds no assertions
// itself; tests/test_plugin_check.cpp (PluginCheck) runs `mbd plugin check` on it and asserts
// the FAIL line of exactly that gamma.
#include <mbd/sdk/plugin.hpp>

namespace {

class BrokenSkate : public mbd::Joint {
public:
    explicit BrokenSkate(const mbd::JointSpec& spec) : u_(spec.markers[1].u_bar), y_(spec.markers[1].axis_y()) {}
    int rows() const override { return 0; }
    void evaluate(const mbd::BodyStates&, mbd::ConstraintEval&) const override {}
    int velocity_rows() const override { return 1; }
    void evaluate_velocity(const mbd::BodyStates& bodies, mbd::VelocityConstraintEval& out) const override {
        const mbd::SpatialBody& j = bodies.spatial(1);
        const mbd::Vec3 y = j.A * y_;
        out.A.block<1, 3>(0, 6) = y.transpose();
        out.A.block<1, 3>(0, 9) = (j.A.transpose() * (j.A * u_).cross(y)).transpose();
        out.b.setZero();
        out.gamma.setZero();  // broken: the quadratic terms are missing
    }

private:
    mbd::Vec3 u_, y_;
};

std::unique_ptr<mbd::Joint> make_broken_skate(const mbd::JointSpec& spec) {
    if (spec.dimension != mbd::Dimension::Spatial) spec.params.fail("broken_skate is spatial only");
    return std::make_unique<BrokenSkate>(spec);
}

}  // namespace

MBD_JOINT_PLUGIN(broken_skate, make_broken_skate)
