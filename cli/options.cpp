// Checked numbers and input files of the subcommands (see options.hpp).
#include "options.hpp"

#include <mbd/app/scene_loader.hpp>
#include <mbd/import/import.hpp>
#include <mbd/import/model_format.hpp>
#include <mbd/output_file.hpp>
#include <mbd/output_times.hpp>
#include <mbd/viewer/animation_export.hpp>
#include <mbd/sdk/text.hpp>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>

namespace mbd::cli {

namespace {

// A validator over the parsed number: `accept` says whether it is in range and
// `expected` describes the range ("a positive number").
CLI::Validator number_check(std::function<bool(double)> accept, std::string expected, std::string description) {
    return CLI::Validator(
        [accept, expected](std::string& text) -> std::string {
            const char* begin = text.c_str();
            char* end = nullptr;
            errno = 0;
            const double x = std::strtod(begin, &end);
            if (end == begin || *end != '\0') return "expected " + expected + ", got '" + text + "'";
            if (!std::isfinite(x) || errno == ERANGE)
                return "expected " + expected + ", got '" + text + "' (not a finite number)";
            if (!accept(x)) return "expected " + expected + ", got " + text;
            return {};
        },
        std::move(description));
}

}  // namespace

CLI::Validator positive_number() {
    return number_check([](double x) { return x > 0.0; }, "a positive number", "POSITIVE");
}

CLI::Validator non_negative_number() {
    return number_check([](double x) { return x >= 0.0; }, "a number >= 0", "NON-NEGATIVE");
}

CLI::Validator finite_number() {
    return number_check([](double) { return true; }, "a finite number", "NUMBER");
}

CLI::Validator number_between(double lo, double hi, const std::string& why) {
    return number_check([lo, hi](double x) { return x >= lo && x <= hi; },
                        "a number from " + format_number(lo) + " to " + format_number(hi) + (why.empty() ? "" : " (" + why + ")"),
                        "[" + format_number(lo) + ", " + format_number(hi) + "]");
}

long TimeGrid::intervals() const { return output_intervals(t_end, step, "--step", "--t-end"); }

void add_time_grid_options(CLI::App* sub, TimeGrid& grid) {
    sub->add_option("--t-end", grid.t_end, "End time [s]")->required()->check(non_negative_number());
    sub->add_option("--step", grid.step, "Output step h [s] (at most 1e7 rows)")->required()->check(positive_number());
}

CLI::App* add_scene_subcommand(CLI::App& app, const std::string& name, const std::string& description,
                               std::string& scene, const std::string& scene_help) {
    CLI::App* sub = app.add_subcommand(name, description);
    sub->add_option("SCENE", scene, scene_help)->required();
    return sub;
}

Model load_scene_file(const std::string& scene, Registry& registry) {
    return import::load_scene_or_model(scene, registry,
                                       [](const std::string& warning) { std::cerr << "mbd: warning: " << warning << '\n'; });
}

Scene read_scene_file(const std::string& scene, Registry& registry) {
    if (import::detect_format(scene) == import::ModelFormat::Scene) return read_scene(scene, registry);
    return scene_of(load_scene_file(scene, registry));
}

std::vector<std::filesystem::path> scene_files(const std::string& scene, const Model& model) {
    std::vector<std::filesystem::path> files{scene};
    for (const std::string& base : model.base_files) files.emplace_back(base);
    return files;
}

void check_animation_output(const std::string& animation, const std::string& scene, const Model& model) {
    if (animation.empty()) return;
    viewer::animation_format(animation);  // a bad name fails before the run
    check_output_path(animation, scene_files(scene, model), "--animation");
}

}  // namespace mbd::cli
