// The compliant contact force 'sphere_sphere' (sphere_contact.hpp, mbd/sdk/contact.hpp).
// Two spheres (spatial); the planar counterpart is circle_circle.
#include "sphere_contact.hpp"

#include <mbd/sdk/plugin.hpp>

#include <memory>

namespace {

std::unique_ptr<mbd::Force> make_sphere_sphere(const mbd::ForceSpec& spec) {
    return std::make_unique<mbd::contact::SphereContact>(spec, mbd::Dimension::Spatial, "circle_circle");
}

}  // namespace

MBD_FORCE_PLUGIN(sphere_sphere, make_sphere_sphere)
