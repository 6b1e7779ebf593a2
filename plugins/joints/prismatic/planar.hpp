// Planar prismatic (translational) joint: two rows (book Eqs. 3.90-3.94, Ex. 3.14),
//   "angle":         (theta^j + phi_j) - (theta^i + phi_i) - c = 0, c its initial value,
//   "perpendicular": h^{iT} r_P^{ij} = 0, h^i = A^i h_bar^i, h_bar^i = marker i's y axis,
// with the corrected Q_d2 (digest Sec. 3.3; the book's L4429 has a spurious term).
// The sliding axis is marker i's x axis. Coordinate: s = axis_i . (R^j - r_P^i).
#pragma once

#include <mbd/sdk/joint.hpp>
#include <mbd/sdk/planar_primitives.hpp>

#include <memory>

namespace mbd::planar {

class PrismaticJoint final : public FramePairJoint {
public:
    using FramePairJoint::FramePairJoint;

    int rows() const override { return 2; }

    std::string row_name(int row) const override { return row == 0 ? "angle" : "perpendicular"; }

    void evaluate(const BodyStates& b, ConstraintEval& out) const override {
        clear(out);
        relative_angle(b, 0, mi_.angle, 1, mj_.angle, c_, out, 0);  // first row of Eq. 3.94
        perpendicular_distance(b, 0, mi_, 1, mj_, out, 1);           // Eq. 3.94, corrected Q_d2
    }

    bool has_coordinate() const override { return true; }
    void coordinate(const BodyStates& b, CoordinateEval& s) const override {
        axial_travel_coordinate(b, 0, mi_, 1, s);
    }

    std::optional<RelativeMotion> relative_motion() const override {
        return RelativeMotion{{prismatic_along(Vec3::UnitX())}};
    }
};

}  // namespace mbd::planar

inline std::unique_ptr<mbd::Joint> make_planar_prismatic(const mbd::JointSpec& spec) {
    return mbd::planar::make_frame_pair_joint<mbd::planar::PrismaticJoint>(spec);
}
