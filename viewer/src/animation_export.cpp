// export_animation: the format from the extension, the output written under NAME.partial
// and renamed only once complete, so an error never leaves a file under the final name.
#include <mbd/viewer/animation_export.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <system_error>

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
    const std::string partial = path + ".partial";
    std::error_code ignored;
    try {
        std::ofstream out(partial, std::ios::binary | std::ios::trunc);
        if (!out) throw std::runtime_error("cannot write '" + partial + "' (does its folder exist?)");
        if (format == AnimationFormat::Glb)
            write_glb(model, table, out);
        else
            write_html(model, table, options, out);
        out.close();
        if (!out) throw std::runtime_error("writing '" + partial + "' failed (disk full?)");
        std::error_code error;
        std::filesystem::rename(partial, path, error);
        if (error) throw std::runtime_error("cannot rename '" + partial + "' to '" + path + "': " + error.message());
    } catch (...) {
        std::filesystem::remove(partial, ignored);
        throw;
    }
}

}  // namespace mbd::viewer
