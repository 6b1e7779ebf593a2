// Spatial fixed (rigid, weld) joint: the joint origins coincide (SPH) and the two
// marker triads stay aligned (DOT1(x_i, z_j), DOT1(y_i, z_j), DOT1(x_i, y_j)).
// This replaces the book's "theta_i - theta_j - k_theta" form of Eqs. 7.183-7.184,
// which is only valid for single-axis rotations (joints digest Sec. 4.2). 6 rows, 0 DOF.
#pragma once

#include <mbd/sdk/joint.hpp>
#include <mbd/sdk/spatial_primitives.hpp>

#include <memory>

namespace mbd::spatial {

class SpatialFixed : public PrimitiveJoint {
public:
    explicit SpatialFixed(const JointSpec& spec) : PrimitiveJoint(spec) {
        add_sph();
        add_dot1(X, Z, "z-parallel-1");
        add_dot1(Y, Z, "z-parallel-2");
        add_dot1(X, Y, "no-twist");
        set_relative_motion(RelativeMotion{});  // no freedoms
    }
};

}  // namespace mbd::spatial

inline std::unique_ptr<mbd::Joint> make_spatial_fixed(const mbd::JointSpec& spec) {
    mbd::spatial::require_spatial_pair(spec, "use the planar fixed variant");
    return std::make_unique<mbd::spatial::SpatialFixed>(spec);
}
