// Animation export of a result (docs/user-guide.md, "Watching the motion"): a glTF 2.0
// binary (.glb) or a self-contained HTML viewer (.html), chosen by the file extension.
#pragma once

#include <mbd/model.hpp>
#include <mbd/viewer/motion_table.hpp>

#include <string>

namespace mbd::viewer {

enum class AnimationFormat { Glb, Html };

// .glb or .html; anything else throws InputError naming the path.
AnimationFormat animation_format(const std::string& path);

struct AnimationOptions {
    std::string plot_column;  // HTML: the column plotted first (default: the first body's first coordinate)
};

// Writes PATH.partial and renames it to PATH once complete; on any error no file is left
// under either name. The table must hold the scene's pose columns (match_pose_columns).
void export_animation(const Model& model, const MotionTable& table, const std::string& path,
                      const AnimationOptions& options = {});

// The two writers behind export_animation, writing to a stream.
void write_glb(const Model& model, const MotionTable& table, std::ostream& out);
void write_html(const Model& model, const MotionTable& table, const AnimationOptions& options, std::ostream& out);

}  // namespace mbd::viewer
