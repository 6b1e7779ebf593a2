// Work-precision benchmarks (`mbd bench`, docs/benchmarks.md): error against CPU time.
//
// A benchmark scene carries a `bench:` key (docs/scene-format.md) that says how long to
// run, what to measure (positions of bodies or body points at the output times, and how
// to reduce them: max over the run, or the final time), against which reference (a closed
// form, a published solution, or a tight-tolerance run cross-checked by a second
// formulation), and which grid of formulation x integrator x tolerance (or step) to run,
// plus the peer engines' models (bench/peers/). Every run gives one BenchRow.
#pragma once

#include <mbd/method_choice.hpp>
#include <mbd/model.hpp>
#include <mbd/registry.hpp>
#include <mbd/scene.hpp>
#include <mbd/simulation.hpp>

#include <Eigen/Core>

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace mbd {

struct BenchMeasure {
    std::vector<std::string> bodies;      // measured bodies (their points, below)
    std::vector<Eigen::Vector3d> points;  // point on each body, body frame (default: mass centre)
    std::string quantity = "position";    // only positions are measured
    std::string norm = "max";             // max: worst over the output times; final: last time only
    std::string describe() const;         // e.g. "max |r - r_ref| of bob over t = 0..10 s"
};

struct BenchReference {
    std::string kind;         // closed_form, published, tight_run
    std::string name;         // closed_form / published: which one
    std::map<std::string, double> params;  // the reference's numeric keys (closed-form parameters)
    // tight_run
    std::string formulation = "augmented", integrator = "dopri5", cross_check = "embedding";
    double tolerance = 1e-12;
};

struct BenchSeries {
    std::string formulation, integrator;
    std::vector<double> tolerances;  // adaptive integrators
    std::vector<double> steps;       // fixed-step integrators
};

struct BenchPeerSeries {
    std::string engine;              // simbody, mujoco, dart
    std::string integrator;          // the peer's own name for it
    std::vector<double> tolerances, steps;
};

struct BenchSpec {
    std::string scene;               // file path
    std::string name;                // scene name
    double t_end = 1.0;
    double output_step = 0.0;        // 0: t_end / 100
    BenchMeasure measure;
    BenchReference reference;
    std::vector<BenchSeries> runs;
    std::string peer_model;          // model name the peer programs know, or a model file's path
    std::vector<std::string> peer_arguments;  // a model file's: measured bodies, initial velocities (peer_common.hpp)
    std::vector<BenchPeerSeries> peers;
};

// The scene section a benchmark reads (scene_sections.hpp).
inline constexpr const char* kBenchSection = "bench";

// Reads the scene's `bench:` section (Scene::sections). Throws InputError (file:line) when it
// is missing or malformed.
BenchSpec load_bench_spec(const Scene& scene);

// Positions of the measured points at the output times: one row per time, 3 columns per point.
struct Trajectory {
    std::vector<double> times;
    Eigen::MatrixXd points;
};

struct BenchReferenceData {
    std::string kind;                // closed_form, published, tight_run
    std::string description;         // e.g. "closed form pendulum_a01 (Jacobi sn)"
    double cross_check = -1.0;       // tight_run: the two formulations' difference in the measure
    Trajectory trajectory;           // at the output times (published: only the given times)
};

// Output times of a benchmark: output_step, 2 output_step, ..., t_end.
std::vector<double> bench_output_times(const BenchSpec& spec);

// A01 closed form: the pendulum pinned at the origin, released at rest, theta from the
// downward vertical; theta(t) = 2 asin(k sn(K(k) - w t, k)), k = sin(theta0 / 2),
// w = sqrt(m g l / J_O) (J_O = J + m l^2 of the scene's body). Returns the mass-centre
// position (3 columns) at the times.
Eigen::MatrixXd pendulum_closed_form(const Model& model, const std::string& body, const std::vector<double>& times);

BenchReferenceData make_bench_reference(const Model& model, Registry& registry, const BenchSpec& spec);

// Run one simulation and sample the measured points at the output times (the CPU time and
// stats of the run are returned in `result`).
Trajectory sample_trajectory(const Model& model, Registry& registry, const SimulationSettings& settings,
                             const BenchMeasure& measure, SimulationResult& result);

// The error of a trajectory against the reference, reduced by measure.norm: the largest
// Euclidean distance of a measured point from its reference over the reference's times
// (norm max) or at the last of them (norm final). Times of the reference that the
// trajectory lacks are an error (std::invalid_argument).
double bench_error(const Trajectory& run, const Trajectory& reference, const BenchMeasure& measure);

struct BenchRow {
    std::string engine = "mbd";      // mbd, simbody, mujoco, dart
    std::string scene, formulation, integrator;
    double tolerance = 0.0;          // 0: fixed step
    double step = 0.0;               // 0: adaptive
    double cpu_s = 0.0;              // median over the repeats
    long steps = 0;
    double error = 0.0;              // NaN when the run failed
    std::string error_measure, reference_kind;
    std::string status = "ok";       // ok, or the failure message
};

struct BenchOptions {
    int repeat = 3;                  // runs per grid point; cpu_s is their median
    std::vector<std::string> peer_dirs;  // folders searched in turn for mbd_peer_<engine> (default_peer_dirs())
    bool progress = true;            // progress bar on stderr when it is a terminal
    std::vector<std::string> only_formulations;  // empty: all of the scene's
    double tolerance_floor = 0.0;    // skip grid tolerances below this, the peers' too (quick runs)
};

struct BenchSceneResult {
    BenchSpec spec;
    MethodChoice automatic;  // what `mbd simulate` picks for the scene when nothing is named (method_choice.hpp)
    BenchReferenceData reference;
    std::vector<BenchRow> rows;
    std::vector<std::string> notes;  // e.g. "peer simbody: not installed (...); skipped"
    int skipped_peer_runs = 0;       // grid points of peers that are not installed (no rows)
};

// The folders of the peer programs built with this mbd, from the running executable's
// location: bin/peers (build tree), then libexec/mbd/peers (install tree).
std::vector<std::string> default_peer_dirs();

// The first `dirs`/mbd_peer_<engine> that is an executable file; else empty, and `missing`
// says which folders were searched and what to do.
std::string peer_executable(const std::vector<std::string>& dirs, const std::string& engine, std::string& missing);

// How a scene's runs ended: ok, failed, skipped (an mbd grid point after a failure of its
// series, or a peer's point when the peer is not installed), for the summary line.
struct BenchTally {
    int ok = 0, failed = 0, skipped = 0, skipped_peers = 0;
    int runs() const { return ok + failed + skipped + skipped_peers; }
};
BenchTally tally(const BenchSceneResult& result);

// Runs the grid of one scene (and its peers). `log` gets the notes as they happen.
BenchSceneResult run_bench_scene(const std::string& scene_file, Registry& registry, const BenchOptions& options,
                                 const std::function<void(const std::string&)>& log = {});

// The same for a model and its spec given (a model file's default spec, bench_model_file.hpp).
BenchSceneResult run_bench(const Model& model, const BenchSpec& spec, Registry& registry, const BenchOptions& options,
                           const std::function<void(const std::string&)>& log = {});

// The CSV (one row per run) and JSON (scenes with their references, and the rows) texts;
// `mbd bench` writes them through OutputFile (output_file.hpp).
std::string bench_csv(const std::vector<BenchSceneResult>& results);
std::string bench_json(const std::vector<BenchSceneResult>& results);

}  // namespace mbd
