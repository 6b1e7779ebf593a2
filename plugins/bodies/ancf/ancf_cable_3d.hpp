// The spatial `ancf_cable` (ancf_cable_3d.cpp): what a spatial scene's `ancf_cable` is made of.
#pragma once

#include <mbd/sdk/body.hpp>

#include <memory>

namespace mbd::ancf {

std::unique_ptr<FlexibleBody> make_spatial_cable(const BodySpec& spec);

}  // namespace mbd::ancf
