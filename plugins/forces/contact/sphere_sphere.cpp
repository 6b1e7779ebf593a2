// The compliant contact force 'sphere_sphere' (sphere_contact.hpp, mbd/sdk/contact.hpp).
// Two spheres (spatial); the planar counterpart is circle_circle.
#include "sphere_contact.hpp"

#include "contact_keys.hpp"

#include <mbd/sdk/plugin.hpp>

#include <memory>

namespace {

std::unique_ptr<mbd::Force> make_sphere_sphere(const mbd::ForceSpec& spec) {
    return std::make_unique<mbd::contact::SphereContact>(spec, mbd::Dimension::Spatial, "circle_circle");
}

}  // namespace

MBD_FORCE_PLUGIN(sphere_sphere, make_sphere_sphere)

// The keys of a scene entry (mbd/sdk/plugin_keys.hpp): `mbd plugin check` builds its test scene
// from the examples; docs/scene-format.md is checked against them (tests/test_plugin_keys.cpp).
namespace {
const mbd::PluginKey sphere_sphere_keys[] = {
    {"radii", "[r_i, r_j] (m), each > 0", nullptr, "[0.4, 0.5]"},
    MBD_CONTACT_LAW_KEYS
    {}};
}  // namespace

MBD_FORCE_KEYS(sphere_sphere, "a sphere on each body", mbd::kTwoBodies, mbd::kSpatialOnly, sphere_sphere_keys)
