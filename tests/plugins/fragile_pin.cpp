// A deliberately fragile joint plugin for the error messages of issue 20: a planar pin
// (book Eqs. 3.93-3.95, rows x and y) whose equations turn NaN from `breaks_at` seconds
// on, as a plugin with a singular formula would, and whose factory throws a bare
// std::invalid_argument (no file, no joint name) when `breaks_at` is not positive.
// Test-only.
#include <mbd/sdk/plugin.hpp>

#include <limits>
#include <stdexcept>

namespace {

class FragilePin : public mbd::Joint {
public:
    FragilePin(const mbd::JointSpec& spec, double breaks_at)
        : ui_(spec.markers[0].u_bar2()), uj_(spec.markers[1].u_bar2()), breaks_at_(breaks_at) {}
    int rows() const override { return 2; }
    std::string row_name(int row) const override { return row == 0 ? "x" : "y"; }
    void evaluate(const mbd::BodyStates& bodies, mbd::ConstraintEval& out) const override {
        const mbd::PlanarBody& i = bodies.planar(0);
        const mbd::PlanarBody& j = bodies.planar(1);
        out.C = i.point(ui_) - j.point(uj_);
        out.J.block<2, 2>(0, 0).setIdentity();
        out.J.block<2, 1>(0, 2) = i.A_theta * ui_;
        out.J.block<2, 2>(0, 3) = -mbd::Mat2::Identity();
        out.J.block<2, 1>(0, 5) = -(j.A_theta * uj_);
        out.C_t.setZero();
        out.gamma = i.omega * i.omega * (i.A * ui_) - j.omega * j.omega * (j.A * uj_);
        if (bodies.t >= breaks_at_) out.C[0] = std::numeric_limits<double>::quiet_NaN();
    }

private:
    mbd::Vec2 ui_, uj_;
    double breaks_at_;
};

std::unique_ptr<mbd::Joint> make_fragile_pin(const mbd::JointSpec& spec) {
    const double breaks_at = spec.params.number("breaks_at");
    if (!(breaks_at > 0.0)) throw std::invalid_argument("breaks_at must be positive");  // deliberately bare
    return std::make_unique<FragilePin>(spec, breaks_at);
}

}  // namespace

MBD_JOINT_PLUGIN(fragile_pin, make_fragile_pin)
