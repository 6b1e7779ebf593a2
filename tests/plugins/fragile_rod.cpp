// A deliberately fragile joint plugin for the error messages of issue 20: a planar
// rod of length `length` from a ground point (the first marker) to a point of the
// second body. Its factory throws a plain std::invalid_argument (no file, no joint
// name) for a length <= 0, and from `breaks_at` seconds on its equations turn NaN,
// as a plugin with a singular formula would. Test-only.
#include <mbd/sdk/plugin.hpp>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace {

class FragileRod : public mbd::Joint {
public:
    FragileRod(const mbd::JointSpec& spec, double length, double breaks_at)
        : ui_(spec.markers[0].u_bar2()), uj_(spec.markers[1].u_bar2()), length_(length), breaks_at_(breaks_at) {}
    int rows() const override { return 1; }
    std::string row_name(int) const override { return "length"; }
    void evaluate(const mbd::BodyStates& bodies, mbd::ConstraintEval& out) const override {
        const mbd::PlanarBody& i = bodies.planar(0);
        const mbd::PlanarBody& j = bodies.planar(1);
        // C = (d.d - L^2) / 2 with d = r_j - r_i: J = d^T [dr_j/dq - dr_i/dq], gamma = -ddot.ddot + d . (terms)
        const mbd::Vec2 d = j.point(uj_) - i.point(ui_);
        const mbd::Vec2 ddot = j.Rdot + j.omega * (j.A_theta * uj_) - i.Rdot - i.omega * (i.A_theta * ui_);
        out.C[0] = 0.5 * (d.dot(d) - length_ * length_);
        out.J.block<1, 2>(0, 0) = -d.transpose();
        out.J(0, 2) = -d.dot(i.A_theta * ui_);
        out.J.block<1, 2>(0, 3) = d.transpose();
        out.J(0, 5) = d.dot(j.A_theta * uj_);
        out.C_t[0] = 0.0;
        // d2/dt2 of d^T d / 2 = ddot.ddot + d.dddot, with dddot's velocity terms -omega^2 A u
        out.gamma[0] = -ddot.dot(ddot) + d.dot(j.omega * j.omega * (j.A * uj_) - i.omega * i.omega * (i.A * ui_));
        if (bodies.t >= breaks_at_) out.C[0] = std::numeric_limits<double>::quiet_NaN();
    }

private:
    mbd::Vec2 ui_, uj_;
    double length_, breaks_at_;
};

std::unique_ptr<mbd::Joint> make_fragile_rod(const mbd::JointSpec& spec) {
    const double length = spec.params.number("length");
    if (!(length > 0.0)) throw std::invalid_argument("length must be positive");  // deliberately bare
    const double breaks_at = spec.params.has("breaks_at") ? spec.params.number("breaks_at") : INFINITY;
    return std::make_unique<FragileRod>(spec, length, breaks_at);
}

}  // namespace

MBD_JOINT_PLUGIN(fragile_rod, make_fragile_rod)
