// mbd stability [SCENE...] [--markdown docs/stability.md]: the stability matrix of the extreme
// cases (issue 8). Runs every scene (default: scenes/extreme/*.yaml) with every formulation the
// registry finds and the integrators of stability_integrators(), each run in a forked
// child with the case's processor-time budget, and writes the case x formulation x integrator matrix
// (app/src/stability.cpp). Exit status 1 when a declared pair misses its declared outcome or a
// child crashed.
#include "commands.hpp"
#include "options.hpp"

#include <mbd/import/import.hpp>
#include <mbd/import/model_format.hpp>
#include <mbd/import/scene_writer.hpp>
#include <mbd/interrupt.hpp>
#include <mbd/output_file.hpp>
#include <mbd/progress_bar.hpp>
#include <mbd/sdk/text.hpp>
#include <mbd/registry.hpp>
#include <mbd/scene.hpp>
#include <mbd/app/stability.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <memory>
#include <optional>

namespace mbd::cli {

namespace {

// A scene as it is; a model file (MJCF, URDF, SDF) imported as `mbd import` does, with the
// outcome it declares none of: `expect: {outcome: pass}` and its defaults (constraint violation
// below 1e-6 over 1 s; docs/import.md). `warn` receives what the import left out.
Scene load_case(const std::filesystem::path& file, Registry& registry, const std::function<void(const std::string&)>& warn) {
    if (import::detect_format(file) == import::ModelFormat::Scene) return read_scene(file, registry);
    const import::ImportedScene scene = import::import_model(file);
    const std::string missing = import::unmapped_summary(scene.unmapped);
    if (!missing.empty() && warn) warn(file.string() + ": not imported: " + missing);
    return read_scene_text(import::scene_yaml(scene) + std::string(kExpectSection) + ": {outcome: pass}\n",
                           file.string() + " (imported)", registry);
}

// The children load their case quietly: the parent warned once when it read it.
Scene load_case_quietly(const std::filesystem::path& file, Registry& registry) { return load_case(file, registry, {}); }

struct StabilityArguments {
    std::vector<std::string> scenes;
    std::string markdown;
    std::vector<std::string> formulations;
    std::vector<std::string> integrators;
    bool quick = false;
    bool quiet = false;
};

// Runs one cell of the matrix (cell `index` of `cells`) in its child, its simulated time on the
// progress line, and prints its matrix line (and a failure's message) above the bar.
CellOutcome run_cell(const StabilityCase& c, const std::string& formulation, const std::string& integrator, bool quick,
                     ProgressBar& bar, int index, int cells) {
    const std::string running = c.name + " " + formulation + " " + integrator;
    auto progress = [&](double t, double t_end) {
        const double part = t_end > 0.0 ? t / t_end : 0.0;
        bar.update((index + part) / cells, running + " t = " + format_number(t, 4) + " / " + format_number(t_end, 4) +
                                               " s, cell " + std::to_string(index + 1) + "/" + std::to_string(cells));
    };
    const CellOutcome o =
        run_case_isolated(c.scene, formulation, integrator, quick ? c.expect.quick_t_end : 0.0, progress, load_case_quietly);
    char line[512];
    std::snprintf(line, sizeof line, "%-28s %-12s %-18s %s (%.1f s)", c.name.c_str(), formulation.c_str(),
                  integrator.c_str(), o.cell().c_str(), o.seconds);
    console_line(line, stdout);
    if (!o.message.empty() && o.kind != "pass") console_line("    " + o.message.substr(0, 300), stdout);
    return o;
}

// "dopri5, dop853, ...": the integrators of the matrix (stability_integrators()).
std::string default_integrators() {
    std::string all;
    for (const std::string& name : stability_integrators()) all += (all.empty() ? "" : ", ") + name;
    return all;
}

}  // namespace

namespace {

// Every scene read first, as the matrix's cases: bad input stops before any run, and the
// --markdown file must not be one of the inputs.
std::vector<StabilityCase> read_cases(const std::vector<std::string>& scenes, const std::string& markdown) {
    std::vector<Scene> models;
    std::vector<std::filesystem::path> inputs;
    for (const std::string& scene : scenes) {
        Registry r;
        models.push_back(load_case(scene, r, [](const std::string& warning) {
            std::cerr << "mbd: warning: " << warning << '\n';
        }));
        for (const auto& file : scene_files(scene, models.back().model)) inputs.push_back(file);
    }
    check_output_path(markdown, inputs, "--markdown");
    std::vector<StabilityCase> cases;
    for (size_t k = 0; k < scenes.size(); ++k) {
        StabilityCase c;
        c.scene = scenes[k];
        c.name = std::filesystem::path(scenes[k]).stem().string();
        c.expect = read_expectation(models[k]);
        cases.push_back(std::move(c));
    }
    return cases;
}

}  // namespace

void add_stability_command(CLI::App& app, Commands& commands) {
    CLI::App* sub = app.add_subcommand("stability", "Run the extreme cases (scenes with an 'expect:' key) with every "
                                                    "formulation and integrator and write the outcome matrix");
    auto args = std::make_shared<StabilityArguments>();
    sub->add_option("SCENE", args->scenes, "Scenes or model files (MJCF, URDF, SDF; default: every scenes/extreme/*.yaml "
                                           "under the current directory)");
    sub->add_option("--markdown", args->markdown, "Write the matrix as Markdown to this file (e.g. docs/stability.md)");
    sub->add_option("--formulation", args->formulations, "Only these formulations (repeatable; default: all found)");
    sub->add_option("--integrator", args->integrators, "Only these integrators (repeatable; default: " + default_integrators() + ")");
    sub->add_flag("--quick", args->quick, "Use each case's quick_t_end (shorter runs)");
    sub->add_flag("-q,--quiet", args->quiet, "No progress line (the running case and its simulated time)");

    commands[sub] = [args] {
        std::vector<std::string> scenes = args->scenes;
        if (scenes.empty()) {
            for (const auto& entry : std::filesystem::directory_iterator("scenes/extreme"))
                if (entry.path().extension() == ".yaml") scenes.push_back(entry.path().string());
            std::sort(scenes.begin(), scenes.end());
        }
        Registry registry;
        std::vector<std::string> formulations = args->formulations;
        if (formulations.empty()) formulations = registry.type_names("formulation");
        std::vector<std::string> integrators = args->integrators;
        if (integrators.empty()) integrators = stability_integrators();

        std::vector<StabilityCase> pending = read_cases(scenes, args->markdown);
        const std::string command =
            std::string("mbd stability") + (args->quick ? " --quick" : "") + " --markdown " + args->markdown;
        InterruptScope stop_on_signal;  // SIGINT/SIGTERM/SIGHUP end the matrix between runs
        std::optional<OutputFile> markdown;
        if (!args->markdown.empty()) markdown.emplace(args->markdown);

        std::vector<StabilityCase> cases;
        int wrong = 0, crashes = 0;
        // the running cell and its simulated time on a progress line; the finished cells above it
        ProgressBar bar(!args->quiet);
        const int cells = static_cast<int>(pending.size() * formulations.size() * integrators.size());
        int cell = 0;
        for (StabilityCase& c : pending) {
            for (const std::string& f : formulations)
                for (const std::string& i : integrators) {
                    stop_if_interrupted();
                    CellOutcome o = run_cell(c, f, i, args->quick, bar, cell++, cells);
                    if (o.kind == "crashed" || o.kind == "error") ++crashes;
                    if (f == c.expect.formulation && i == c.expect.integrator && !outcome_matches(c.expect, o)) ++wrong;
                    c.cells.push_back(o);
                }
            if (args->quick) c.expect.t_end = c.expect.quick_t_end;
            cases.push_back(std::move(c));
            // the cases done so far, in NAME.partial until the matrix is complete
            if (markdown)
                markdown->replace(stability_markdown(cases, formulations, integrators, command),
                                  "the matrix of the first " + std::to_string(cases.size()) + " of " +
                                      std::to_string(pending.size()) + " cases");
        }
        bar.finish();
        if (markdown) {
            markdown->commit();
            std::printf("wrote %s\n", args->markdown.c_str());
        }
        std::printf("%zu cases: %d declared pairs missed their declared outcome, %d crashes or errors\n", cases.size(),
                    wrong, crashes);
        return wrong > 0 || crashes > 0 ? 1 : 0;
    };
}

}  // namespace mbd::cli
