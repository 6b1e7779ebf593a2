// Spatial prismatic (translational) joint (book Eqs. 7.177-7.180): z_j parallel to
// z_i (DOT1(x_i, z_j), DOT1(y_i, z_j)), the origin of frame j on the z_i axis
// (DOT2(x_i, d), DOT2(y_i, d)) and no twist about it (DOT1(x_i, y_j)).
// 5 rows, 1 DOF: the travel z_i . (R_j - r_P^i) of body j's mass centre along z_i.
#pragma once

#include <mbd/sdk/joint.hpp>
#include <mbd/sdk/spatial_primitives.hpp>

#include <memory>

namespace mbd::spatial {

class SpatialPrismatic : public PrimitiveJoint {
public:
    explicit SpatialPrismatic(const JointSpec& spec) : PrimitiveJoint(spec) {
        add_dot1(X, Z, "z-parallel-1");  // Eq. 7.178, rows 1-2
        add_dot1(Y, Z, "z-parallel-2");
        add_dot2(X, "on-axis-1");        // Eq. 7.178, rows 3-4
        add_dot2(Y, "on-axis-2");
        add_dot1(X, Y, "no-twist");      // Eq. 7.177 (h_i . h_j)
        set_relative_motion(RelativeMotion{{prismatic_along(Vec3::UnitZ())}});
    }

    bool has_coordinate() const override { return true; }
    void coordinate(const BodyStates& bodies, CoordinateEval& out) const override {
        write(out, travel_along_z(Pair(bodies), marker_i(), Vec3::Zero()), /*periodic=*/false);
    }
};

}  // namespace mbd::spatial

inline std::unique_ptr<mbd::Joint> make_spatial_prismatic(const mbd::JointSpec& spec) {
    mbd::spatial::require_spatial_pair(spec, "use the planar prismatic variant");
    return std::make_unique<mbd::spatial::SpatialPrismatic>(spec);
}
