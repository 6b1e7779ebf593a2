// The compliant contact force 'circle_circle' (sphere_contact.hpp, mbd/sdk/contact.hpp).
// Two circles (planar); the spatial counterpart is sphere_sphere.
#include "sphere_contact.hpp"

#include "contact_keys.hpp"

#include <mbd/sdk/plugin.hpp>

#include <memory>

namespace {

std::unique_ptr<mbd::Force> make_circle_circle(const mbd::ForceSpec& spec) {
    return std::make_unique<mbd::contact::SphereContact>(spec, mbd::Dimension::Planar, "sphere_sphere");
}

}  // namespace

MBD_FORCE_PLUGIN(circle_circle, make_circle_circle)

// The keys of a scene entry (mbd/sdk/plugin_keys.hpp): `mbd plugin check` builds its test scene
// from the examples; docs/scene-format.md is checked against them (tests/test_plugin_keys.cpp).
namespace {
const mbd::PluginKey circle_circle_keys[] = {
    {"radii", "[r_i, r_j] (m), each > 0", nullptr, "[0.4, 0.5]"},
    MBD_CONTACT_LAW_KEYS
    {}};
}  // namespace

MBD_FORCE_KEYS(circle_circle, "a circle on each body", mbd::kTwoBodies, mbd::kPlanarOnly, circle_circle_keys)
