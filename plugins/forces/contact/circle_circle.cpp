// The compliant contact force 'circle_circle' (sphere_contact.hpp, mbd/sdk/contact.hpp).
// Two circles (planar); the spatial counterpart is sphere_sphere.
#include "sphere_contact.hpp"

#include <mbd/sdk/plugin.hpp>

#include <memory>

namespace {

std::unique_ptr<mbd::Force> make_circle_circle(const mbd::ForceSpec& spec) {
    return std::make_unique<mbd::contact::SphereContact>(spec, mbd::Dimension::Planar, "sphere_sphere");
}

}  // namespace

MBD_FORCE_PLUGIN(circle_circle, make_circle_circle)
