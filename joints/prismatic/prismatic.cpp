// The prismatic joint plugin: planar (planar.hpp) and spatial (spatial.hpp) variants in one library.
#include "planar.hpp"
#include "spatial.hpp"

#include <mbd/sdk/plugin.hpp>

namespace {

std::unique_ptr<mbd::Joint> make_prismatic(const mbd::JointSpec& spec) {
    return spec.dimension == mbd::Dimension::Planar ? make_planar_prismatic(spec) : make_spatial_prismatic(spec);
}

}  // namespace

MBD_JOINT_PLUGIN(prismatic, make_prismatic)
