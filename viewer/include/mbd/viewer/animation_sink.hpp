// The animation as an output sink (mbd/output_sink.hpp): `mbd simulate --animation` takes its
// frames from the run's rows as they come, not from the CSV read back. The rows are kept in
// memory and the animation (animation_export.hpp) is written at end(), when the run is
// complete; a failed or stopped run writes none.
#pragma once

#include <mbd/model.hpp>
#include <mbd/output_sink.hpp>
#include <mbd/viewer/animation_export.hpp>

#include <memory>
#include <string>

namespace mbd::viewer {

// A sink writing the animation of `model` to `path` (.glb or .html, animation_format).
std::unique_ptr<OutputSink> make_animation_sink(const Model& model, const std::string& path,
                                                const AnimationOptions& options = {});

}  // namespace mbd::viewer
