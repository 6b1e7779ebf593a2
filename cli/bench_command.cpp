// mbd bench SCENE...: work-precision benchmark (error against CPU time, docs/benchmarks.md).
// Every scene's `bench:` key gives its measure, reference and grid; a model file (URDF, MJCF)
// gets the default spec of bench_model_file.hpp. Each grid point is run --repeat times (median
// CPU time). Writes one CSV and one JSON row per run.
#include "bench_model_file.hpp"
#include "commands.hpp"
#include "options.hpp"

#include <mbd/app/bench.hpp>
#include <mbd/import/model_format.hpp>
#include <mbd/sdk/text.hpp>
#include <mbd/interrupt.hpp>
#include <mbd/output_file.hpp>
#include <mbd/progress_bar.hpp>
#include <mbd/registry.hpp>
#include <mbd/scene.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>

namespace mbd::cli {

namespace {

struct BenchArguments {
    std::vector<std::string> scenes;
    std::string csv = "bench.csv";
    std::string json = "bench.json";
    int repeat = 3;
    std::string peers;
    std::vector<std::string> formulations;
    double tolerance_floor = 0.0;
    bool quiet = false;
};

// "NAME: 12 runs (9 ok, 1 failed, 2 skipped after a failure of their series); 8 peer runs
// skipped (not installed: simbody); reference ...; best mbd CPU at error <= 1e-6: ..."
std::string summary_line(const BenchSceneResult& r) {
    const BenchTally t = tally(r);
    std::string line = r.spec.name + ": " + std::to_string(t.runs()) + " runs (" + std::to_string(t.ok) + " ok, " +
                       std::to_string(t.failed) + " failed, " + std::to_string(t.skipped) +
                       " skipped after a failure of their series)";
    if (t.skipped_peers > 0) {
        std::string engines;  // from the notes "peer ENGINE: not installed (...); skipped"
        for (const std::string& note : r.notes)
            if (note.rfind("peer ", 0) == 0 && note.find(": not installed") != std::string::npos)
                engines += (engines.empty() ? "" : ", ") + note.substr(5, note.find(':') - 5);
        line += "; " + std::to_string(t.skipped_peers) + " peer runs skipped (not installed: " + engines + ")";
    }
    double best_cpu_at = NAN, best_err = NAN;
    for (const BenchRow& row : r.rows)
        if (row.engine == "mbd" && row.status == "ok" && row.error <= 1e-6 && !(row.cpu_s >= best_cpu_at)) {
            best_cpu_at = row.cpu_s;
            best_err = row.error;
        }
    return line + "; reference " + r.reference.description + "; best mbd CPU at error <= 1e-6: " +
           (std::isfinite(best_cpu_at) ? format_number(best_cpu_at, 3) + " s (error " + format_number(best_err, 3) + ")"
                                       : std::string("not reached"));
}

}  // namespace

void add_bench_command(CLI::App& app, Commands& commands) {
    CLI::App* sub = app.add_subcommand(
        "bench", "Work-precision benchmark: run each scene's grid of formulation x integrator x tolerance (or step), "
                 "measure the error against its reference and the CPU time");
    auto args = std::make_shared<BenchArguments>();
    sub->add_option("SCENE", args->scenes,
                    "Benchmark scenes (YAML with a 'bench:' key), or model files (URDF, MJCF: the default spec of "
                    "docs/benchmarks.md, run by every peer that reads the file)")->required();
    sub->add_option("--csv", args->csv, "CSV output (one row per run)")->capture_default_str();
    sub->add_option("--json", args->json, "JSON output (scenes with their references, and the rows)")
        ->capture_default_str();
    sub->add_option("--repeat", args->repeat, "Runs per grid point; the CPU time is their median")
        ->capture_default_str()
        ->check(positive_number());
    sub->add_option("--peers", args->peers,
                    "Folder of the peer programs (mbd_peer_simbody, mbd_peer_mujoco, mbd_peer_dart); default: the peers built with "
                    "this mbd (bin/peers beside it, or libexec/mbd/peers when installed); a missing one is reported "
                    "and its runs skipped");
    sub->add_option("--formulation", args->formulations, "Only these formulations (repeatable)");
    sub->add_option("--min-tol", args->tolerance_floor, "Skip grid tolerances below this, the peers' too (a quick run)")
        ->check(non_negative_number());
    sub->add_flag("-q,--quiet", args->quiet, "No progress bar and no summary");

    commands[sub] = [args] {
        Registry registry;
        // the outputs must not be a scene or one of its base files, nor each other
        std::vector<std::filesystem::path> inputs;
        auto is_model_file = [](const std::string& file) { return import::detect_format(file) != import::ModelFormat::Scene; };
        for (const std::string& scene : args->scenes) {
            Registry scene_registry;
            if (is_model_file(scene)) inputs.emplace_back(scene);
            else
                for (const auto& file : scene_files(scene, load_scene(scene, scene_registry))) inputs.push_back(file);
        }
        check_output_path(args->csv, inputs, "--csv");
        inputs.emplace_back(args->csv);
        check_output_path(args->json, inputs, "--json");
        InterruptScope stop_on_signal;  // SIGINT/SIGTERM/SIGHUP end the benchmark between runs
        OutputFile csv(args->csv), json(args->json);
        BenchOptions options;
        options.repeat = args->repeat;
        options.peer_dirs = args->peers.empty() ? default_peer_dirs() : std::vector<std::string>{args->peers};
        options.progress = !args->quiet;
        options.only_formulations = args->formulations;
        options.tolerance_floor = args->tolerance_floor;
        std::vector<BenchSceneResult> results;
        const auto start = std::chrono::steady_clock::now();
        for (const std::string& scene : args->scenes) {
            const auto log = [&](const std::string& text) {
                console_line("mbd bench: " + scene + ": " + text);  // above the progress bar
            };
            if (is_model_file(scene)) {
                const ModelFileBench bench = model_file_bench(scene, registry);
                results.push_back(run_bench(bench.model, bench.spec, registry, options, log));
            } else {
                results.push_back(run_bench_scene(scene, registry, options, log));
            }
            // the scenes done so far, in NAME.partial until the end
            const std::string done = "the runs of the first " + std::to_string(results.size()) + " of " +
                                     std::to_string(args->scenes.size()) + " scenes";
            csv.replace(bench_csv(results), done);
            json.replace(bench_json(results), done);
            if (!args->quiet) std::printf("%s\n", summary_line(results.back()).c_str());
            std::fflush(stdout);
        }
        csv.commit();
        json.commit();
        if (!args->quiet) {
            const double wall =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            std::printf("wrote %s and %s (%.1f s wall)\n", args->csv.c_str(), args->json.c_str(), wall);
        }
        return 0;
    };
}

}  // namespace mbd::cli
