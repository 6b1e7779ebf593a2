// Stability matrix of the extreme cases (issue 8): every scene of scenes/extreme declares,
// under its top-level `expect:` key, the outcome it must end in (a pass with an error
// measure and a bound, or a named failure). This module reads that declaration, runs a
// case with one formulation and one integrator (in process, or in a forked child with a
// processor-time budget so that a hang or a crash becomes a named outcome), classifies the
// result and writes the case x formulation x integrator matrix (docs/stability.md).
#pragma once

#include <mbd/app/scene_loader.hpp>
#include <mbd/model.hpp>
#include <mbd/registry.hpp>

#include <functional>
#include <string>
#include <vector>

namespace mbd {

// The scene's `expect:` key.
//   expect: {outcome: pass, measure: oscillator | energy | momentum | rotation | a01 | final | constraints,
//            bound: B, also_accept: [kind, ...], <measure>: {...}, formulation: F, integrator: I,
//            t_end: T, quick_t_end: Tq, output_step: H, tolerance: TOL, step: STEP, budget: S,
//            rho_infinity: R}
//   expect: {outcome: failure, kind: K | [K, ...], ...same run keys}
// Failure kinds: step_size_collapse, newton_divergence, singular_constraints,
// redundant_constraints, assembly_failure, projection_failure, blow_up, max_steps,
// solver_failure, budget_exceeded, singular_mass_matrix.
struct Expectation {
    bool pass = true;
    std::vector<std::string> kinds;   // accepted failure kinds (failure), or also-accepted ones (pass)
    std::string measure = "constraints";
    double bound = 1e-6;
    std::string formulation = "augmented", integrator = "dopri5";  // the declared pair
    double t_end = 1.0, quick_t_end = 0.0;
    double output_step = 0.0;         // 0: t_end / 200
    double tolerance = 1e-8;          // adaptive integrators
    double step = 0.0;                // generalized_alpha (0: output_step / 10)
    double rho_infinity = 0.8;
    double budget = 30.0;             // wall seconds per run
    // measure parameters
    std::string body;
    double amplitude = 0.0, omega = 0.0, length = 1.0;
    Vec3 axis = Vec3::UnitZ();
    std::vector<std::string> final_bodies;  // final: positions at t_end, e.g. a published solution
    std::vector<Vec3> final_positions;
};

// The scene section a stability case reads (scene_sections.hpp).
inline constexpr const char* kExpectSection = "expect";

// The scene's `expect:` section (Scene::sections). Throws InputError when the scene has none, or
// a malformed one.
Expectation read_expectation(const Scene& scene);

struct CellOutcome {
    std::string kind;        // "pass", "inaccurate", a failure kind, "not_applicable", "crashed", "error"
    double error = -1.0;     // the measure (pass / inaccurate); -1 when none
    double bound = 0.0;
    double time = -1.0;      // simulated time of the failure (-1: unknown / none)
    double seconds = 0.0;    // wall time
    int signal = 0;          // crashed: the child's signal
    std::string message;     // the engine's message (failures)
    std::string cell() const;  // the matrix text, e.g. "pass (error 3e-09)"
};

// How far a running case got: the simulated time t of its run to t_end.
using CaseProgress = std::function<void(double t, double t_end)>;

// Run one case in this process (t_end <= 0: the expectation's t_end); `progress` gets the
// time of each output sample. The formulation's messages are dropped (the cell says how the
// case ended).
CellOutcome run_case(const Model& model, Registry& registry, const Expectation& expect,
                     const std::string& formulation, const std::string& integrator, double t_end = 0.0,
                     const CaseProgress& progress = {});

// Run one case in a forked child that loads the scene itself; the parent kills it after
// budget + 10 s (budget_exceeded) and reports a signal as "crashed". The child reports its
// simulated time through the pipe (at most ten times a second); `progress` gets the latest
// about every 0.1 s while the parent waits (before the first report: t = 0, t_end = 0). The
// scene is read by `load` (scene_loader.hpp).
CellOutcome run_case_isolated(const std::string& scene, const std::string& formulation,
                              const std::string& integrator, double t_end = 0.0, const CaseProgress& progress = {},
                              const SceneLoader& load = {});

// Does the outcome satisfy the declaration?
bool outcome_matches(const Expectation& expect, const CellOutcome& outcome);

// Integrators of the matrix: every one of integrator_descriptions() but the first-order euler.
std::vector<std::string> stability_integrators();

struct StabilityCase {
    std::string scene, name;
    Expectation expect;
    std::vector<CellOutcome> cells;  // formulation-major: formulations x integrators
};

// Markdown report of the matrix.
std::string stability_markdown(const std::vector<StabilityCase>& cases, const std::vector<std::string>& formulations,
                               const std::vector<std::string>& integrators, const std::string& command);

}  // namespace mbd
