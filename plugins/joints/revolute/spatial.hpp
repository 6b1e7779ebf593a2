// Spatial revolute joint (book Eqs. 7.175-7.176, "variant B"): the joint origins
// coincide (SPH, 3 rows) and z_j stays parallel to z_i (DOT1(x_i, z_j), DOT1(y_i, z_j)).
// 5 rows, 1 DOF: the rotation angle of frame j about z_i, atan2(y_i . x_j, x_i . x_j).
#pragma once

#include <mbd/sdk/joint.hpp>
#include <mbd/sdk/spatial_primitives.hpp>

#include <memory>

namespace mbd::spatial {

class SpatialRevolute : public PrimitiveJoint {
public:
    explicit SpatialRevolute(const JointSpec& spec) : PrimitiveJoint(spec) {
        add_sph();                      // Eq. 7.159
        add_dot1(X, Z, "z-parallel-1");  // Eq. 7.175
        add_dot1(Y, Z, "z-parallel-2");
        set_relative_motion(RelativeMotion{{revolute_about(Vec3::UnitZ())}});
    }

    bool has_coordinate() const override { return true; }
    void coordinate(const BodyStates& bodies, CoordinateEval& out) const override {
        write(out, angle_about_z(Pair(bodies), marker_i(), marker_j()), /*periodic=*/true);
    }
    bool gamma_depends_on_translation() const override { return false; }  // SPH, DOT1s, atan2 of DOT1s
};

}  // namespace mbd::spatial

inline std::unique_ptr<mbd::Joint> make_spatial_revolute(const mbd::JointSpec& spec) {
    mbd::spatial::require_spatial_pair(spec, "use the planar revolute variant");
    return std::make_unique<mbd::spatial::SpatialRevolute>(spec);
}
