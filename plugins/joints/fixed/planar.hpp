// Planar fixed (weld) joint: three rows, the joint points coincide ("x", "y", book Eq. 3.129)
// and the relative angle of the joint frames is held at its initial value ("angle", Eq. 3.80
// with f = const). No coordinate; as a tree edge it has no freedoms.
#pragma once

#include <mbd/sdk/joint.hpp>
#include <mbd/sdk/planar_primitives.hpp>

#include <memory>

namespace mbd::planar {

class FixedJoint final : public FramePairJoint {
public:
    using FramePairJoint::FramePairJoint;

    int rows() const override { return 3; }

    std::string row_name(int row) const override {
        return row == 0 ? "x" : row == 1 ? "y" : "angle";
    }

    void evaluate(const BodyStates& b, ConstraintEval& out) const override {
        clear(out);
        point_coincidence(b, 0, mi_.u_bar2(), 1, mj_.u_bar2(), out, 0);  // Eqs. 3.129-3.133
        relative_angle(b, 0, mi_.angle, 1, mj_.angle, c_, out, 2);
    }

    std::optional<RelativeMotion> relative_motion() const override { return RelativeMotion{}; }
};

}  // namespace mbd::planar

inline std::unique_ptr<mbd::Joint> make_planar_fixed(const mbd::JointSpec& spec) {
    return mbd::planar::make_frame_pair_joint<mbd::planar::FixedJoint>(spec);
}
