// The compliant contact force 'sphere_plane' (plane_contact.hpp, mbd/sdk/contact.hpp).
// A sphere on a plane (spatial); the planar counterpart is circle_line.
#include "plane_contact.hpp"

#include "contact_keys.hpp"

#include <mbd/sdk/plugin.hpp>

#include <memory>

namespace {

std::unique_ptr<mbd::Force> make_sphere_plane(const mbd::ForceSpec& spec) {
    return std::make_unique<mbd::contact::PlaneContact>(spec, mbd::Dimension::Spatial, "circle_line");
}

}  // namespace

MBD_FORCE_PLUGIN(sphere_plane, make_sphere_plane)

// The keys of a scene entry (mbd/sdk/plugin_keys.hpp): `mbd plugin check` builds its test scene
// from the examples; docs/scene-format.md is checked against them (tests/test_plugin_keys.cpp).
namespace {
const mbd::PluginKey sphere_plane_keys[] = {
    {"normal", "the plane's normal in body i's axes, non-zero, towards the sphere", nullptr, "[-0.3, -0.4, -0.866]"},
    {"radius", "the sphere's radius (m), > 0", nullptr, "10"},
    MBD_CONTACT_LAW_KEYS
    {}};
}  // namespace

MBD_FORCE_KEYS(sphere_plane, "a sphere on body j against a plane of body i", mbd::kTwoBodies, mbd::kSpatialOnly, sphere_plane_keys)
