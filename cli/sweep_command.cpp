// mbd sweep STUDY.yaml -o results.h5 [--threads N] [--resume] [--csv table.csv]: a parameter
// study (design studies, tolerance analyses, Monte Carlo runs; docs/sweep.md). In one process
// with --threads N, or under mpirun across ranks (rank 0 the master and only writer, the
// other ranks ask it for cases one at a time).
#include "commands.hpp"
#include "options.hpp"

#include <mbd/app/input_fingerprint.hpp>
#include <mbd/app/scene_loader.hpp>
#include <mbd/app/study.hpp>
#include <mbd/app/study_design.hpp>
#include <mbd/app/sweep_mpi.hpp>
#include <mbd/app/sweep_results.hpp>
#include <mbd/app/sweep_runner.hpp>
#include <mbd/import/import.hpp>
#include <mbd/interrupt.hpp>
#include <mbd/output_file.hpp>
#include <mbd/output_lock.hpp>
#include <mbd/registry.hpp>

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>

namespace mbd::cli {

namespace {

// Every file the study reads: the study file, its base scene and the scene's `base:` files.
std::vector<std::filesystem::path> study_files(const Study& study) {
    std::vector<std::filesystem::path> files{study.file};
    for (const std::filesystem::path& f : scene_files(study.scene.string(), *study.model)) files.push_back(f);
    return files;
}

struct SweepArguments {
    std::string study;
    std::string output;
    std::string csv;
    int threads = 1;
    bool resume = false;
    bool quiet = false;
    double flush_seconds = 1.0;
};

// The output files are neither an input (the study, its scene and their bases) nor, for the
// results file, anything but a regular file or a new name: it is written as OUTPUT.partial and
// renamed, which would put a regular file in place of a device (/dev/null), a FIFO or a socket.
void check_outputs(const SweepArguments& a, const std::vector<std::filesystem::path>& inputs) {
    check_output_path(a.output, inputs, "--output");
    check_output_path(a.csv, inputs, "--csv");
    if (!a.csv.empty() && std::filesystem::absolute(a.csv) == std::filesystem::absolute(a.output))
        throw InputError("--csv", "'" + a.csv + "' is also the --output file; give the table another name");
    std::error_code ec;
    const std::filesystem::file_status status = std::filesystem::status(a.output, ec);
    if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status))
        throw InputError("--output", "'" + a.output + "' is not a regular file (a device, FIFO or socket): the "
                                     "HDF5 results are written beside it and renamed over it, which would replace "
                                     "it; give the name of a regular file (--csv may name a device)");
}

// Under the output's lock: without --resume, the unfinished results of an earlier run are not
// overwritten.
void check_no_unfinished_results(const SweepArguments& a) {
    std::error_code ec;
    const std::string partial = a.output + ".partial";
    if (!a.resume && std::filesystem::exists(partial, ec))
        throw InputError("--output", "'" + partial + "' holds the unfinished results of an earlier run: continue it "
                                     "with --resume, or remove it to start anew");
}

void print_summary(const SweepArguments& a, const SweepResults& results, const SweepStats& stats, double seconds) {
    if (a.quiet) return;
    std::printf("swept %s: %ld cases (%ld run now), %ld failed, in %.3g s (%.4g cases/s)\n", a.study.c_str(),
                results.cases(), stats.cases_run, results.failed(), seconds,
                seconds > 0 ? static_cast<double>(stats.cases_run) / seconds : 0.0);
    if (stats.cases_run > 0)
        std::printf("  master overhead %.3g us CPU per case (recording, writing, serving the workers)\n",
                    1e6 * stats.recorder_cpu_seconds / static_cast<double>(stats.cases_run));
    std::printf("  results in %s%s%s\n", a.output.c_str(), a.csv.empty() ? "" : ", table in ", a.csv.c_str());
}

// Rank 0 (or the only process): the outputs checked, the results file opened, the cases run.
int run_sweep(const SweepArguments& a, const MpiRole& role) {
    Registry registry;
    // the study's scene may be a model file (MJCF, URDF, SDF), imported with its one warning
    const Study study = read_study(a.study, registry, [](const std::filesystem::path& file, Registry& r) {
        return read_scene_file(file.string(), r);
    });
    const CaseDesign design(study);  // each case made when it runs: no table of the cases
    if (role.launched && a.threads != 1)
        throw InputError("--threads", "under mpirun every rank runs one case at a time: give more ranks "
                                      "(mpirun -np N) instead of --threads");
    const std::vector<std::filesystem::path> inputs = study_files(study);
    check_outputs(a, inputs);
    InterruptScope stop_on_signal;  // SIGINT/SIGTERM/SIGHUP: the finished cases stay in OUTPUT.partial
    const OutputLock lock(a.output, "--output", "mbd sweep " + a.study);  // for the whole run
    check_no_unfinished_results(a);
    const std::vector<InputFingerprint> contents = fingerprint_inputs(inputs);
    SweepResults results = a.resume ? SweepResults::resume(a.output, study, design, contents)
                                    : SweepResults::create(a.output, study, design, contents);
    results.set_flush_interval(a.flush_seconds);
    const auto start = std::chrono::steady_clock::now();
    SweepOptions options;
    options.threads = a.threads;
    options.progress = !a.quiet && ::isatty(STDERR_FILENO);
    SweepStats stats;
    try {
        stats = role.launched ? run_sweep_master(study, registry, design, results, options)
                              : run_sweep_threads(study, registry, design, results, options);
    } catch (const Interrupted&) {
        std::cerr << "mbd: '" << results.partial_path().string() << "' holds the " << results.finished() << " of "
                  << results.cases() << " cases finished; continue with --resume\n";
        throw;
    }
    if (!a.csv.empty()) results.write_csv(a.csv);
    print_summary(a, results, stats, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    return 0;
}

}  // namespace

void add_sweep_command(CLI::App& app, Commands& commands) {
    const auto [args, sub] = scene_subcommand<SweepArguments>(
        app, "sweep",
        "Parameter study: run the study file's analysis over a grid, Latin hypercube or Monte Carlo design of "
        "scene parameters, in threads or MPI ranks (mpirun -np N mbd sweep ...); results in one HDF5 file",
        "Study file (YAML, docs/sweep.md)", &SweepArguments::study);
    sub->add_option("-o,--output", args->output, "Results file (HDF5)")->required();
    sub->add_option("--csv", args->csv, "Also write the table of parameters and metrics as CSV");
    sub->add_option("--threads", args->threads, "Threads in this process (one Model, a Data per thread)")
        ->capture_default_str()
        ->check(CLI::Range(1, 1024));
    sub->add_flag("--resume", args->resume,
                  "Continue an interrupted study from OUTPUT.partial: finished cases are kept, the others run once");
    sub->add_option("--flush-seconds", args->flush_seconds,
                    "Least time between syncs of the journal OUTPUT.partial (a kill loses at most the cases of this time)")
        ->capture_default_str()
        ->check(positive_number());
    sub->add_flag("-q,--quiet", args->quiet, "No progress bar and no summary");

    commands[sub] = [args = args] {
        const MpiRole role = mpi_role();
        if (role.launched && role.rank != 0) {
            Registry registry;
            std::optional<Study> study;
            std::optional<CaseDesign> design;
            try {
                study = read_study(args->study, registry, [](const std::filesystem::path& file, Registry& r) {
                    return scene_of(import::load_scene_or_model(file, r, {}));  // rank 0 warns
                });
                design.emplace(*study);
            } catch (const InputError&) {
                return 2;  // rank 0 reads the same study and reports the error once
            }
            return run_sweep_worker(*study, registry, *design);
        }
        try {
            return run_sweep(*args, role);
        } catch (const Interrupted&) {
            throw;
        } catch (...) {
            release_workers(role);  // bad input found by rank 0 alone (the outputs): the workers wait for it
            throw;
        }
    };
}

}  // namespace mbd::cli
