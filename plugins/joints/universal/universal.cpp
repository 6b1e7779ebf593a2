// Universal (Hooke) joint (book Eqs. 7.181-7.182): the joint origins coincide (SPH)
// and the cross-bar z_i (fixed in body i, the scene's axes[0]) stays perpendicular
// to the cross-bar x_j (fixed in body j, axes[1]): DOT1(z_i, x_j). The core builds the
// markers from `axes: [a1, a2]` and rejects non-perpendicular axes. 4 rows, 2 DOF.
// Spatial only.
#include <mbd/sdk/plugin.hpp>
#include <mbd/sdk/plugin_keys.hpp>
#include <mbd/sdk/spatial_primitives.hpp>

#include <memory>

std::unique_ptr<mbd::Joint> make_universal(const mbd::JointSpec& spec) {
    using namespace mbd::spatial;
    auto joint = primitive_joint(spec, "in a planar scene use a 'revolute' joint");
    joint->add_sph();                          // Eq. 7.182, rows 1-3
    joint->add_dot1(Z, X, "cross-bar-perp");  // Eq. 7.182, row 4 (h_i . h_j)
    joint->set_relative_motion(mbd::RelativeMotion{
        {revolute_about(mbd::Vec3::UnitZ()), revolute_about(mbd::Vec3::UnitX())}});
    return joint;
}

MBD_JOINT_PLUGIN(universal, make_universal)

// The keys of a scene entry (mbd/sdk/plugin_keys.hpp): `mbd plugin check` builds its test scene
// from the examples; docs/scene-format.md is checked against them (tests/test_plugin_keys.cpp).
namespace {
const mbd::PluginKey universal_keys[] = {
    {}};
}  // namespace

MBD_JOINT_KEYS(universal, "a Hooke joint with cross-bar `axes: [a1, a2]`", mbd::kTwoBodies, mbd::kSpatialOnly, universal_keys)
