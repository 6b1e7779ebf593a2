// The prismatic joint plugin: planar (planar.hpp) and spatial (spatial.hpp) variants in one library.
#include "planar.hpp"
#include "spatial.hpp"

#include <mbd/sdk/plugin.hpp>
#include <mbd/sdk/plugin_keys.hpp>

namespace {

std::unique_ptr<mbd::Joint> make_prismatic(const mbd::JointSpec& spec) {
    return spec.dimension == mbd::Dimension::Planar ? make_planar_prismatic(spec) : make_spatial_prismatic(spec);
}

}  // namespace

MBD_JOINT_PLUGIN(prismatic, make_prismatic)

// The keys of a scene entry (mbd/sdk/plugin_keys.hpp): `mbd plugin check` builds its test scene
// from the examples; docs/scene-format.md is checked against them (tests/test_plugin_keys.cpp).
namespace {
const mbd::PluginKey prismatic_keys[] = {
    {}};
}  // namespace

MBD_JOINT_KEYS(prismatic, "a slider: relative translation along `axis`, no relative rotation", mbd::kTwoBodies, mbd::kPlanarAndSpatial, prismatic_keys)
