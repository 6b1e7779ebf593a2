// Shared pieces of the subcommands' options: numbers checked when parsed (finite,
// in range; the error names the option, the value and the range), and the files a
// run reads, which an output must never overwrite (mbd/output_file.hpp).
#pragma once

#include <mbd/scene.hpp>
#include <mbd/integrator.hpp>  // kSmallestTolerance
#include <mbd/model.hpp>
#include <mbd/registry.hpp>

#include <CLI/CLI.hpp>

#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace mbd::cli {

// A finite number > 0 ("nan", "inf", 0 and negatives are refused).
CLI::Validator positive_number();
// A finite number >= 0.
CLI::Validator non_negative_number();
// Any finite number.
CLI::Validator finite_number();
// A finite number in [lo, hi]; `why` (may be empty) explains the range in the error.
CLI::Validator number_between(double lo, double hi, const std::string& why = "");

// A subcommand that reads one scene: NAME with its description, on `app`, and its required
// SCENE positional bound to `scene`.
CLI::App* add_scene_subcommand(CLI::App& app, const std::string& name, const std::string& description,
                               std::string& scene, const std::string& scene_help = "Scene file (YAML)");

// The same, with the subcommand's arguments made here (shared with the action it registers):
// `const auto [args, sub] = scene_subcommand<SimulateArguments>(app, "simulate", "...");`.
// The positional binds to Arguments::scene unless `file` names another member.
template <class Arguments>
std::pair<std::shared_ptr<Arguments>, CLI::App*> scene_subcommand(CLI::App& app, const std::string& name,
                                                                  const std::string& description,
                                                                  const std::string& scene_help = "Scene file (YAML)",
                                                                  std::string Arguments::*file = &Arguments::scene) {
    auto args = std::make_shared<Arguments>();
    return {args, add_scene_subcommand(app, name, description, (*args).*file, scene_help)};
}

// The scene a subcommand reads: an mbd scene, or a model file (MJCF, URDF) imported, the format
// known from the file's content (docs/import.md); what an import leaves out is warned of on stderr.
Model load_scene_file(const std::string& scene, Registry& registry);
// The same as a Scene: an mbd scene with its application sections and its document as read
// (`mbd statics --output` rewrites it); a model file's has none.
Scene read_scene_file(const std::string& scene, Registry& registry);

// The scene file and every `base:` file it inherits from.
std::vector<std::filesystem::path> scene_files(const std::string& scene, const Model& model);

// The output times t = 0, h, 2h, ..., t_end of mbd kinematics and mbd inverse
// (--t-end, --step, both required).
struct TimeGrid {
    double t_end = 0.0;
    double step = 0.0;
    // The number of intervals; throws InputError (naming --step and --t-end) beyond 1e7 rows.
    long intervals() const;
};
void add_time_grid_options(CLI::App* sub, TimeGrid& grid);

// `--animation FILE` of simulate and statics, checked before the run: a name the viewer writes
// (.glb or .html) that is none of the run's input files. Empty: no animation, nothing to check.
void check_animation_output(const std::string& animation, const std::string& scene, const Model& model);

}  // namespace mbd::cli
