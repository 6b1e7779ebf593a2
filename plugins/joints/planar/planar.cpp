// Planar joint: body j moves in the x-y plane of the joint frame on body i.
// z_i is perpendicular to x_j and y_j (DOT1(z_i, x_j), DOT1(z_i, y_j)), so the frames
// stay parallel about z, and the origin of frame j stays in the plane (DOT2(z_i, d)).
// Built from the book's primitives (Remarks, L11362). 3 rows, 3 DOF. Spatial only.
#include <mbd/sdk/plugin.hpp>
#include <mbd/sdk/plugin_keys.hpp>
#include <mbd/sdk/spatial_primitives.hpp>

#include <memory>

std::unique_ptr<mbd::Joint> make_planar(const mbd::JointSpec& spec) {
    using namespace mbd::spatial;
    auto joint = primitive_joint(spec,
                                 "in a planar scene every body already moves in the plane: remove the "
                                 "joint (leave the body free) or use a 'prismatic' or 'revolute' joint");
    joint->add_dot1(Z, X, "z-normal-1");
    joint->add_dot1(Z, Y, "z-normal-2");
    joint->add_dot2(Z, "in-plane");
    joint->set_relative_motion(mbd::RelativeMotion{{prismatic_along(mbd::Vec3::UnitX()),
                                                    prismatic_along(mbd::Vec3::UnitY()),
                                                    revolute_about(mbd::Vec3::UnitZ())}});
    return joint;
}

MBD_JOINT_PLUGIN(planar, make_planar)

// The keys of a scene entry (mbd/sdk/plugin_keys.hpp): `mbd plugin check` builds its test scene
// from the examples; docs/scene-format.md is checked against them (tests/test_plugin_keys.cpp).
namespace {
const mbd::PluginKey planar_keys[] = {
    {}};
}  // namespace

MBD_JOINT_KEYS(planar, "body j moves in the plane through `point` with normal `axis`", mbd::kTwoBodies, mbd::kSpatialOnly, planar_keys)
