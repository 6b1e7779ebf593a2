// Cylindrical joint (book Eqs. 7.168-7.170): z_j parallel to z_i (DOT1(x_i, z_j),
// DOT1(y_i, z_j)) and the origin of frame j on the z_i axis (DOT2(x_i, d), DOT2(y_i, d)).
// 4 rows, 2 DOF (translation along and rotation about z). Spatial only.
#include <mbd/sdk/plugin.hpp>
#include <mbd/sdk/plugin_keys.hpp>
#include <mbd/sdk/spatial_primitives.hpp>

#include <memory>

std::unique_ptr<mbd::Joint> make_cylindrical(const mbd::JointSpec& spec) {
    using namespace mbd::spatial;
    auto joint = primitive_joint(spec,
                                 "in a planar scene use a 'prismatic' joint (axis in the plane) or a "
                                 "'revolute' joint (axis normal to the plane)");
    joint->add_dot1(X, Z, "z-parallel-1");  // Eq. 7.169, rows 1-2
    joint->add_dot1(Y, Z, "z-parallel-2");
    joint->add_dot2(X, "on-axis-1");        // Eq. 7.169, rows 3-4
    joint->add_dot2(Y, "on-axis-2");
    joint->set_relative_motion(mbd::RelativeMotion{
        {prismatic_along(mbd::Vec3::UnitZ()), revolute_about(mbd::Vec3::UnitZ())}});
    return joint;
}

MBD_JOINT_PLUGIN(cylindrical, make_cylindrical)

// The keys of a scene entry (mbd/sdk/plugin_keys.hpp): `mbd plugin check` builds its test scene
// from the examples; docs/scene-format.md is checked against them (tests/test_plugin_keys.cpp).
namespace {
const mbd::PluginKey cylindrical_keys[] = {
    {}};
}  // namespace

MBD_JOINT_KEYS(cylindrical, "rotation about and translation along `axis`", mbd::kTwoBodies, mbd::kSpatialOnly, cylindrical_keys)
