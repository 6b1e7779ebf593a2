// export_animation: the format from the extension; the file is written through OutputFile,
// so an error never leaves a file under the final name, and a failed export leaves none.
#include <mbd/viewer/animation_export.hpp>

#include <mbd/output_file.hpp>

#include <filesystem>

namespace mbd::viewer {

AnimationFormat animation_format(const std::string& path) {
    const std::string ext = std::filesystem::path(path).extension().string();
    if (ext == ".glb") return AnimationFormat::Glb;
    if (ext == ".html" || ext == ".htm") return AnimationFormat::Html;
    throw InputError(path, "an animation is written as .glb (glTF 2.0 binary) or .html (a browser viewer); got '" +
                               ext + "'");
}

void export_animation(const Model& model, const MotionTable& table, const std::string& path,
                      const AnimationOptions& options) {
    const AnimationFormat format = animation_format(path);
    match_pose_columns(model, table);  // before any file appears
    if (format == AnimationFormat::Html) match_flexible_columns(model, table);  // the page draws them (.glb: not yet)
    OutputFile file(path);             // the output contract of every command (output_file.hpp)
    DocumentStream out(file);          // written as it is produced: no copy of a large export in memory
    if (format == AnimationFormat::Glb)
        write_glb(model, table, out);
    else
        write_html(model, table, options, out);
    out.flush();
    file.commit();
}

}  // namespace mbd::viewer
