// mbd export SCENE -o model.xml | model.urdf: a scene (or model file) as MJCF for MuJoCo or URDF
// for ROS tools (docs/import.md, "Export"), written only after its own parser has read it back;
// what the format cannot hold is listed in one warning (an error, exit 2, with --strict).
#include "commands.hpp"
#include "options.hpp"

#include <mbd/import/export_tree.hpp>
#include <mbd/import/imported_scene.hpp>  // unmapped_summary
#include <mbd/import/model_writers.hpp>
#include <mbd/kinematics.hpp>  // KinematicsError
#include <mbd/output_file.hpp>
#include <mbd/registry.hpp>

#include <iostream>

namespace mbd::cli {

namespace {

struct ExportArguments {
    std::string scene;
    std::string output;
    bool strict = false;
};

// The format asked for, from the output's name: .xml / .mjcf MJCF, .urdf URDF.
bool wants_urdf(const std::string& output) {
    const std::string ext = std::filesystem::path(output).extension().string();
    if (ext == ".urdf") return true;
    if (ext == ".xml" || ext == ".mjcf") return false;
    throw InputError("--output", "'" + output + "': name the model file .xml or .mjcf (MJCF, for MuJoCo) or .urdf (URDF)");
}

// The tree of the scene at its assembled start. A scene that cannot be assembled has no start
// to export: bad input (exit 2), named with the assembly's reason.
import::ExportTree export_tree_of(const Model& model, const std::string& scene) {
    try {
        return import::build_export_tree(model);
    } catch (const KinematicsError& e) {
        throw InputError(scene, std::string("cannot be exported: its initial state cannot be assembled (") + e.what() +
                                    "); fix the bodies' initial positions or the joints and drivers that cannot "
                                    "hold there (mbd check shows the same)");
    }
}

}  // namespace

void add_export_command(CLI::App& app, Commands& commands) {
    const auto [args, sub] = scene_subcommand<ExportArguments>(
        app, "export", "Write a scene as an MJCF (MuJoCo) or URDF (ROS) model file; list what the format cannot hold",
        "Scene file (YAML) or model file (MJCF, URDF, SDF)");
    sub->add_option("-o,--output", args->output, "The model file to write: NAME.xml (MJCF) or NAME.urdf (URDF)")->required();
    sub->add_flag("--strict", args->strict, "Refuse the scene (exit 2, nothing written) when anything is left out");
    commands[sub] = [args = args] {
        const bool urdf = wants_urdf(args->output);
        Registry registry;
        const Model model = load_scene_file(args->scene, registry);
        check_output_path(args->output, scene_files(args->scene, model), "--output");
        import::ExportTree tree = export_tree_of(model, args->scene);
        const std::string text = urdf ? import::urdf_text(tree, tree.left_out) : import::mjcf_text(tree);
        const std::string missing = import::unmapped_summary(tree.left_out);
        if (!missing.empty() && args->strict)
            throw InputError(args->scene, "--strict: the export would leave out " + missing);
        urdf ? import::check_written_urdf(text, args->output) : import::check_written_mjcf(text, args->output);
        OutputFile file(args->output);
        file.write_document_part(text);
        file.commit();
        if (!missing.empty()) std::cerr << "mbd: warning: " << args->scene << ": not exported: " << missing << "\n";
        size_t joints = 0;
        for (const import::ExportBody& body : tree.bodies) joints += body.joints.size();
        std::cout << "exported " << args->scene << " as " << (urdf ? "URDF" : "MJCF") << ": " << tree.bodies.size()
                  << " bodies, " << joints << " joints -> " << args->output << "\n";
        return 0;
    };
}

}  // namespace mbd::cli
