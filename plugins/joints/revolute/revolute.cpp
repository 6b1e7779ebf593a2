// The revolute joint plugin: planar (planar.hpp) and spatial (spatial.hpp) variants in one library.
#include "planar.hpp"
#include "spatial.hpp"

#include <mbd/sdk/plugin.hpp>
#include <mbd/sdk/plugin_keys.hpp>

namespace {

std::unique_ptr<mbd::Joint> make_revolute(const mbd::JointSpec& spec) {
    return spec.dimension == mbd::Dimension::Planar ? make_planar_revolute(spec) : make_spatial_revolute(spec);
}

}  // namespace

MBD_JOINT_PLUGIN(revolute, make_revolute)

// The keys of a scene entry (mbd/sdk/plugin_keys.hpp): `mbd plugin check` builds its test scene
// from the examples; docs/scene-format.md is checked against them (tests/test_plugin_keys.cpp).
namespace {
const mbd::PluginKey revolute_keys[] = {
    {}};
}  // namespace

MBD_JOINT_KEYS(revolute, "a pin: relative rotation about one axis (planar: the plane normal)", mbd::kTwoBodies, mbd::kPlanarAndSpatial, revolute_keys)
