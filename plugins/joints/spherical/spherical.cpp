// Spherical (ball) joint: the joint origins coincide (SPH, book Eqs. 7.159-7.166).
// 3 rows, 3 rotational DOF. Spatial only.
#include <mbd/sdk/plugin.hpp>
#include <mbd/sdk/plugin_keys.hpp>
#include <mbd/sdk/spatial_primitives.hpp>

#include <memory>

std::unique_ptr<mbd::Joint> make_spherical(const mbd::JointSpec& spec) {
    using namespace mbd::spatial;
    auto joint = primitive_joint(spec, "in a planar scene use a 'revolute' joint (a point connection)");
    joint->add_sph();
    // A ball has no axis; the axis field is unused (set to z for definiteness).
    joint->set_relative_motion(mbd::RelativeMotion{{{mbd::RelativeMotion::Kind::Ball, mbd::Vec3::UnitZ(), 0.0}}});
    return joint;
}

MBD_JOINT_PLUGIN(spherical, make_spherical)

// The keys of a scene entry (mbd/sdk/plugin_keys.hpp): `mbd plugin check` builds its test scene
// from the examples; docs/scene-format.md is checked against them (tests/test_plugin_keys.cpp).
namespace {
const mbd::PluginKey spherical_keys[] = {
    {}};
}  // namespace

MBD_JOINT_KEYS(spherical, "a ball joint: the joint points coincide", mbd::kTwoBodies, mbd::kSpatialOnly, spherical_keys)
