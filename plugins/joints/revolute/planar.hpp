// Planar revolute (pin) joint: two rows, the joint points of bodies i and j coincide
// (book Eqs. 3.85-3.88, Jacobian 3.130, Q_d 3.133). Coordinate: s = theta^j - theta^i (Eq. 3.80).
#pragma once

#include <mbd/sdk/joint.hpp>
#include <mbd/sdk/planar_primitives.hpp>

#include <memory>

namespace mbd::planar {

class RevoluteJoint final : public Joint {
public:
    RevoluteJoint(const Marker& mi, const Marker& mj) : u_bar_i_(mi.u_bar2()), u_bar_j_(mj.u_bar2()) {}

    int rows() const override { return 2; }

    void evaluate(const BodyStates& b, ConstraintEval& out) const override {
        clear(out);
        point_coincidence(b, 0, u_bar_i_, 1, u_bar_j_, out, 0);  // Eqs. 3.129-3.133
    }

    std::string row_name(int row) const override { return row == 0 ? "x" : "y"; }
    // gamma = omega_i^2 A_i u_i - omega_j^2 A_j u_j (Eq. 3.133); the relative angle's is 0
    bool gamma_depends_on_translation() const override { return false; }
    bool has_gamma_velocity_transpose() const override { return true; }
    void gamma_velocity_transpose(const BodyStates& b, const double* weights, double* out) const override {
        point_coincidence_gamma_gradient(b, 0, u_bar_i_, 1, u_bar_j_, weights, out);
    }

    bool has_coordinate() const override { return true; }
    void coordinate(const BodyStates& b, CoordinateEval& s) const override {
        relative_angle_coordinate(b, 0, 1, s);  // Eq. 3.80, not periodic
    }

    std::optional<RelativeMotion> relative_motion() const override {
        return RelativeMotion{{revolute_about(Vec3::UnitZ())}};
    }

private:
    Vec2 u_bar_i_, u_bar_j_;
};

}  // namespace mbd::planar

inline std::unique_ptr<mbd::Joint> make_planar_revolute(const mbd::JointSpec& spec) {
    mbd::planar::check_spec(spec, 2, 2, true);
    return std::make_unique<mbd::planar::RevoluteJoint>(spec.markers[0], spec.markers[1]);
}
