// The compliant contact force 'sphere_plane' (plane_contact.hpp, mbd/sdk/contact.hpp).
// A sphere on a plane (spatial); the planar counterpart is circle_line.
#include "plane_contact.hpp"

#include <mbd/sdk/plugin.hpp>

#include <memory>

namespace {

std::unique_ptr<mbd::Force> make_sphere_plane(const mbd::ForceSpec& spec) {
    return std::make_unique<mbd::contact::PlaneContact>(spec, mbd::Dimension::Spatial, "circle_line");
}

}  // namespace

MBD_FORCE_PLUGIN(sphere_plane, make_sphere_plane)
