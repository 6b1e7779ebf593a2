// The fixed joint plugin: planar (planar.hpp) and spatial (spatial.hpp) variants in one library.
#include "planar.hpp"
#include "spatial.hpp"

#include <mbd/sdk/plugin.hpp>
#include <mbd/sdk/plugin_keys.hpp>

namespace {

std::unique_ptr<mbd::Joint> make_fixed(const mbd::JointSpec& spec) {
    return spec.dimension == mbd::Dimension::Planar ? make_planar_fixed(spec) : make_spatial_fixed(spec);
}

}  // namespace

MBD_JOINT_PLUGIN(fixed, make_fixed)

// The keys of a scene entry (mbd/sdk/plugin_keys.hpp): `mbd plugin check` builds its test scene
// from the examples; docs/scene-format.md is checked against them (tests/test_plugin_keys.cpp).
namespace {
const mbd::PluginKey fixed_keys[] = {
    {}};
}  // namespace

MBD_JOINT_KEYS(fixed, "a weld: the bodies keep their initial relative pose", mbd::kTwoBodies, mbd::kPlanarAndSpatial, fixed_keys)
