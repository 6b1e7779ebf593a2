// mbd animate SCENE RESULT.csv -o out.glb | out.html: the motion of a result as a glTF 2.0
// binary or a self-contained browser viewer (viewer/, docs/user-guide.md "Watching the
// motion"). The CSV must be a result of this scene (its body columns are checked).
#include "commands.hpp"
#include "options.hpp"

#include <mbd/output_file.hpp>
#include <mbd/registry.hpp>
#include <mbd/scene.hpp>
#include <mbd/viewer/animation_export.hpp>

#include <cstdio>
#include <memory>

namespace mbd::cli {

namespace {

struct AnimateArguments {
    std::string scene;
    std::string result;
    std::string output;
    std::string plot;
};

}  // namespace

void add_animate_command(CLI::App& app, Commands& commands) {
    const auto [args, sub] = scene_subcommand<AnimateArguments>(
        app, "animate", "Write the motion of a result CSV as a glTF 2.0 binary (.glb) or a browser viewer (.html)",
        "Scene file (YAML) the result was computed from");
    sub->add_option("RESULT", args->result, "Result CSV of mbd simulate or mbd kinematics")->required();
    sub->add_option("-o,--output", args->output, "out.glb (glTF 2.0 binary) or out.html (viewer)")->required();
    sub->add_option("--plot", args->plot, "HTML: the column plotted when the page opens (default: the first body's x)");

    commands[sub] = [args = args] {
        viewer::animation_format(args->output);  // a bad name fails before any work
        Registry registry;
        const Model model = load_scene_file(args->scene, registry);
        std::vector<std::filesystem::path> inputs = scene_files(args->scene, model);
        inputs.emplace_back(args->result);
        check_output_path(args->output, inputs, "--output");
        const viewer::MotionTable table = viewer::read_motion_csv(args->result);
        viewer::AnimationOptions options;
        options.plot_column = args->plot;
        viewer::export_animation(model, table, args->output, options);
        std::printf("wrote %s: %d bodies, %zu rows, t = %g to %g s\n", args->output.c_str(), model.body_count(),
                    table.rows(), table.at(0, 0), table.at(table.rows() - 1, 0));
        return 0;
    };
}

}  // namespace mbd::cli
