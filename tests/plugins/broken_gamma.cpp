// A deliberately broken joint plugin for `mbd plugin check`: a planar pin
// joint whose constraint and Jacobian are right but whose gamma has the wrong
// sign (the book's Q_d, Eq. 3.133, negated). Test-only.
#include <mbd/sdk/plugin.hpp>

namespace {

class BrokenPin : public mbd::Joint {
public:
    explicit BrokenPin(const mbd::JointSpec& spec) : ui_(spec.markers[0].u_bar2()), uj_(spec.markers[1].u_bar2()) {}
    int rows() const override { return 2; }
    void evaluate(const mbd::BodyStates& bodies, mbd::ConstraintEval& out) const override {
        const mbd::PlanarBody& i = bodies.planar(0);
        const mbd::PlanarBody& j = bodies.planar(1);
        out.C = i.point(ui_) - j.point(uj_);
        out.J.block<2, 2>(0, 0).setIdentity();
        out.J.block<2, 1>(0, 2) = i.A_theta * ui_;
        out.J.block<2, 2>(0, 3) = -mbd::Mat2::Identity();
        out.J.block<2, 1>(0, 5) = -(j.A_theta * uj_);
        out.C_t.setZero();
        // correct: omega_i^2 A_i u_i - omega_j^2 A_j u_j; broken: the opposite sign
        out.gamma = -(i.omega * i.omega * (i.A * ui_) - j.omega * j.omega * (j.A * uj_));
    }

private:
    mbd::Vec2 ui_, uj_;
};

std::unique_ptr<mbd::Joint> make_broken_pin(const mbd::JointSpec& spec) {
    if (spec.dimension != mbd::Dimension::Planar) spec.params.fail("broken_pin is planar only");
    return std::make_unique<BrokenPin>(spec);
}

}  // namespace

MBD_JOINT_PLUGIN(broken_pin, make_broken_pin)
