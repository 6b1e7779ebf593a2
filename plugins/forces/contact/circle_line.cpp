// The compliant contact force 'circle_line' (plane_contact.hpp, mbd/sdk/contact.hpp).
// A circle on a line (planar); the spatial counterpart is sphere_plane.
#include "plane_contact.hpp"

#include <mbd/sdk/plugin.hpp>

#include <memory>

namespace {

std::unique_ptr<mbd::Force> make_circle_line(const mbd::ForceSpec& spec) {
    return std::make_unique<mbd::contact::PlaneContact>(spec, mbd::Dimension::Planar, "sphere_plane");
}

}  // namespace

MBD_FORCE_PLUGIN(circle_line, make_circle_line)
