// The compliant contact force 'circle_line' (plane_contact.hpp, mbd/sdk/contact.hpp).
// A circle on a line (planar); the spatial counterpart is sphere_plane.
#include "plane_contact.hpp"

#include "contact_keys.hpp"

#include <mbd/sdk/plugin.hpp>

#include <memory>

namespace {

std::unique_ptr<mbd::Force> make_circle_line(const mbd::ForceSpec& spec) {
    return std::make_unique<mbd::contact::PlaneContact>(spec, mbd::Dimension::Planar, "sphere_plane");
}

}  // namespace

MBD_FORCE_PLUGIN(circle_line, make_circle_line)

// The keys of a scene entry (mbd/sdk/plugin_keys.hpp): `mbd plugin check` builds its test scene
// from the examples; docs/scene-format.md is checked against them (tests/test_plugin_keys.cpp).
namespace {
const mbd::PluginKey circle_line_keys[] = {
    {"normal", "the line's normal in body i's axes, non-zero, towards the circle", nullptr, "[0.6, 0.8]"},
    {"radius", "the circle's radius (m), > 0", nullptr, "10"},
    MBD_CONTACT_LAW_KEYS
    {}};
}  // namespace

MBD_FORCE_KEYS(circle_line, "a circle on body j against a line of body i", mbd::kTwoBodies, mbd::kPlanarOnly, circle_line_keys)
