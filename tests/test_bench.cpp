// The work-precision benchmark's own error computation (app/src/bench.cpp), `mbd simulate
// --error-estimate`, and a missing peer engine. No timings are checked.
#include "support/test_support.hpp"

#include <mbd/app/bench.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace mbd {
namespace {

const std::string kPendulum = "bench/a01-pendulum.yaml";

BenchSpec short_pendulum_spec() {
    BenchSpec spec = load_bench_spec(read_scene(test::scene_path(kPendulum), test::shared_registry()));
    spec.t_end = 2.0;
    spec.output_step = 0.25;
    return spec;
}

TEST(Bench, SpecOfThePendulumScene) {
    const BenchSpec spec = load_bench_spec(read_scene(test::scene_path(kPendulum), test::shared_registry()));
    EXPECT_EQ(spec.reference.kind, "closed_form");
    EXPECT_EQ(spec.reference.name, "pendulum_a01");
    ASSERT_EQ(spec.measure.bodies.size(), 1u);
    EXPECT_EQ(spec.measure.bodies[0], "bob");
    EXPECT_EQ(spec.measure.norm, "max");
    EXPECT_FALSE(spec.runs.empty());
}

TEST(Bench, ClosedFormStartsAtTheReleasePointAndConservesLength) {
    const Model model = load_scene(test::scene_path(kPendulum), test::shared_registry());
    const Eigen::MatrixXd r = pendulum_closed_form(model, "bob", {0.0, 0.3, 1.0, 2.0});
    EXPECT_NEAR(r(0, 0), 1.0, 1e-12);
    EXPECT_NEAR(r(0, 1), 0.0, 1e-12);
    for (int k = 0; k < r.rows(); ++k) EXPECT_NEAR(r.row(k).norm(), 1.0, 1e-12);
    // the bob falls: y < 0 after the release
    EXPECT_LT(r(1, 1), -0.1);
}

// RK4 on the pendulum (embedding: a pure ODE in the joint angle) against the closed form at
// two steps: the measured error falls by ~2^4 = 16 when the step is halved.
TEST(Bench, Rk4ErrorRatioOnThePendulumIsSixteen) {
    Registry& registry = test::shared_registry();
    const BenchSpec spec = short_pendulum_spec();
    const Model model = load_scene(spec.scene, registry);
    const BenchReferenceData ref = make_bench_reference(model, registry, spec);
    ASSERT_EQ(ref.kind, "closed_form");
    double errors[2];
    const double steps[2] = {0.02, 0.01};
    for (int k = 0; k < 2; ++k) {
        SimulationSettings s;
        s.formulation = "embedding";
        s.integrator = "rk4";
        s.integration.step = steps[k];
        s.t_end = spec.t_end;
        s.output_step = spec.output_step;
        s.progress = false;
        SimulationResult result;
        const Trajectory tr = sample_trajectory(model, registry, s, spec.measure, result);
        errors[k] = bench_error(tr, ref.trajectory, spec.measure);
    }
    const double ratio = errors[0] / errors[1];
    EXPECT_GT(errors[1], 1e-9);  // well above round-off, so the ratio is the truncation error's
    EXPECT_GT(ratio, 12.0) << errors[0] << " " << errors[1];
    EXPECT_LT(ratio, 20.0) << errors[0] << " " << errors[1];
}

TEST(Bench, ErrorNormsMaxAndFinal) {
    Trajectory ref, run;
    ref.times = run.times = {1.0, 2.0};
    ref.points = Eigen::MatrixXd::Zero(2, 3);
    run.points = Eigen::MatrixXd::Zero(2, 3);
    run.points(0, 0) = 3.0;  // |e| = 3 at t = 1
    run.points(1, 1) = 1.0;  // |e| = 1 at t = 2
    BenchMeasure m{{"b"}, {Eigen::Vector3d::Zero()}, "position", "max"};
    EXPECT_DOUBLE_EQ(bench_error(run, ref, m), 3.0);
    m.norm = "final";
    EXPECT_DOUBLE_EQ(bench_error(run, ref, m), 1.0);
    run.times = {1.0, 2.5};
    EXPECT_THROW(bench_error(run, ref, m), std::invalid_argument);
}

// `mbd simulate --error-estimate` on the pendulum: the estimate (difference to a run at a ten
// times tighter tolerance) is within a factor of 10 of the true error (closed form).
TEST(Bench, ErrorEstimateOfSimulateIsWithinTenOfTheTrueError) {
    const std::string csv = (std::filesystem::temp_directory_path() / "mbd_test_bench_estimate.csv").string();
    const auto r = test::run_mbd("simulate " + test::scene_path(kPendulum).string() +
                                 " --t-end 3 --tol 1e-6 --output-step 0.1 --error-estimate --json -q -o " + csv);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const nlohmann::json summary = nlohmann::json::parse(r.out);
    const double estimate = summary.at("error_estimate").at("position_error").get<double>();
    EXPECT_TRUE(summary.at("cpu_s").is_number()) << r.out;

    // true error from the CSV: bob.x, bob.y (columns 1, 2) against the closed form
    const Model model = load_scene(test::scene_path(kPendulum), test::shared_registry());
    std::ifstream in(csv);
    std::string line;
    std::getline(in, line);  // header
    double truth = 0.0;
    int rows = 0;
    while (std::getline(in, line)) {
        std::istringstream ls(line);
        std::string field;
        double v[3];
        for (int k = 0; k < 3 && std::getline(ls, field, ','); ++k) v[k] = std::stod(field);
        const Eigen::MatrixXd exact = pendulum_closed_form(model, "bob", {v[0]});
        truth = std::max(truth, std::hypot(v[1] - exact(0, 0), v[2] - exact(0, 1)));
        ++rows;
    }
    std::filesystem::remove(csv);
    EXPECT_EQ(rows, 31);
    ASSERT_GT(truth, 0.0);
    EXPECT_GT(estimate, truth / 10.0) << "estimate " << estimate << ", true " << truth;
    EXPECT_LT(estimate, truth * 10.0) << "estimate " << estimate << ", true " << truth;

    // the text form ends with the summary line
    const auto t = test::run_mbd("simulate " + test::scene_path(kPendulum).string() +
                                 " --t-end 0.5 --step 0.01 --integrator rk4 --error-estimate -o " + csv);
    ASSERT_EQ(t.exit_code, 0) << t.err;
    EXPECT_NE(t.out.find("error estimate: CPU time"), std::string::npos) << t.out;
    std::filesystem::remove(csv);
}

// The pendulum scene with another `bench:` key: its measure and reference, then `runs`
// (the YAML of the runs and peers keys, indented by two) in a scene file under `dir`.
std::string pendulum_bench_scene(const std::filesystem::path& dir, const std::string& runs) {
    std::filesystem::create_directories(dir);
    const std::string scene = (dir / "pendulum.yaml").string();
    std::ifstream src(test::scene_path(kPendulum));
    std::ofstream out(scene);
    std::string line;
    while (std::getline(src, line) && line.rfind("bench:", 0) != 0) out << line << '\n';
    out << "bench:\n  t_end: 1\n  output_step: 0.5\n"
           "  measure: {body: bob, quantity: position, norm: max}\n"
           "  reference: {kind: closed_form, name: pendulum_a01}\n"
        << runs;
    return scene;
}

// A grid given as a geometric sequence: per_decade N is the ratio 10^(1/N) exactly, a ratio R
// is met or beaten by equal ratios from `from` to `to`, both ends included.
TEST(Bench, GridAsAGeometricSequence) {
    const std::string scene = pendulum_bench_scene(
        std::filesystem::temp_directory_path() / "mbd_test_bench_grid",
        "  runs:\n    - {integrator: dopri5, tolerances: {from: 1.0e-4, to: 1.0e-8, per_decade: 2}}\n"
        "    - {integrator: rk4, steps: {from: 1.0e-2, to: 1.0e-3, ratio: 1.5}}\n");
    Registry& registry = test::shared_registry();
    const BenchSpec spec = load_bench_spec(read_scene(scene, registry));
    ASSERT_EQ(spec.runs.size(), 2u);
    const std::vector<double>& tol = spec.runs[0].tolerances;
    ASSERT_EQ(tol.size(), 9u);
    for (int k = 0; k < 9; ++k) EXPECT_NEAR(tol[k] / (1e-4 * std::pow(10.0, -0.5 * k)), 1.0, 1e-13) << k;
    const std::vector<double>& h = spec.runs[1].steps;
    ASSERT_EQ(h.size(), 7u);  // ln 10 / ln 1.5 = 5.68 intervals: 6, each 10^(1/6) = 1.468
    EXPECT_EQ(h.front(), 1e-2);
    EXPECT_EQ(h.back(), 1e-3);
    for (size_t k = 1; k < h.size(); ++k) EXPECT_NEAR(h[k - 1] / h[k], std::pow(10.0, 1.0 / 6.0), 1e-12);
}

TEST(Bench, BadGridsAreRefusedByKey) {
    Registry& registry = test::shared_registry();
    const auto dir = std::filesystem::temp_directory_path() / "mbd_test_bench_bad_grid";
    const std::pair<const char*, const char*> cases[] = {
        {"{from: 1.0e-4, to: 1.0e-8}", "per_decade: N} or {from: A, to: B, ratio: R}"},
        {"{from: 1.0e-4, to: 1.0e-8, ratio: 0.5}", "'ratio' must be a number above 1"},
        {"{from: 1.0e-4, to: -1.0e-8, per_decade: 2}", "'from' and 'to' must be two different positive numbers"},
        {"{from: 1.0e-4, to: 1.0e-8, per_decade: 2, by: 3}", "unknown key 'by'"},
        {"[1.0e-4, 0]", "'tolerances' must be positive numbers"},
    };
    for (const auto& [grid, message] : cases) {
        const std::string scene =
            pendulum_bench_scene(dir, std::string("  runs:\n    - {integrator: dopri5, tolerances: ") + grid + "}\n");
        try {
            load_bench_spec(read_scene(scene, registry));
            ADD_FAILURE() << grid << " was accepted";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("pendulum.yaml:"), std::string::npos) << e.what();
        }
    }
}

// Issue 13's fair bench: no gap in a committed grid wider than sqrt(10) in tolerance or 1.5 in
// step, so that the cost at equal error is interpolated between close points.
TEST(Bench, EveryBenchSceneGridIsFine) {
    int series = 0;
    auto check = [&series](const std::string& what, std::vector<double> values, double widest) {
        std::sort(values.begin(), values.end());
        for (size_t k = 1; k < values.size(); ++k)
            EXPECT_LE(values[k] / values[k - 1], widest * (1 + 1e-12)) << what << " at " << values[k - 1];
        series += values.size() > 1;
    };
    for (const auto& entry : std::filesystem::directory_iterator(test::scene_path("bench"))) {
        if (entry.path().extension() != ".yaml") continue;
        const BenchSpec spec =
            load_bench_spec(read_scene(test::scene_path("bench/" + entry.path().filename().string()), test::shared_registry()));
        for (const BenchSeries& s : spec.runs) {
            check(spec.name + " " + s.formulation + " + " + s.integrator + " tolerances", s.tolerances, std::sqrt(10.0));
            check(spec.name + " " + s.formulation + " + " + s.integrator + " steps", s.steps, 1.5);
        }
        for (const BenchPeerSeries& s : spec.peers) {
            check(spec.name + " " + s.engine + " tolerances", s.tolerances, std::sqrt(10.0));
            check(spec.name + " " + s.engine + " steps", s.steps, 1.5);
        }
    }
    EXPECT_GE(series, 40);
}

// The bench measures the automatic choice of every scene (so its report can set it beside the
// best of grid): the pair `mbd simulate` picks for the scene is one of the scene's series.
TEST(Bench, EveryBenchSceneRunsItsAutomaticChoice) {
    int scenes = 0;
    for (const auto& entry : std::filesystem::directory_iterator(test::scene_path("bench"))) {
        if (entry.path().extension() != ".yaml") continue;
        const Scene scene = read_scene(test::scene_path("bench/" + entry.path().filename().string()), test::shared_registry());
        const Model& model = scene.model;
        const BenchSpec spec = load_bench_spec(scene);
        const MethodChoice automatic = automatic_method(model, spec.t_end);
        bool found = false;
        for (const BenchSeries& s : spec.runs)
            found = found || (s.formulation == automatic.formulation && s.integrator == automatic.integrator);
        EXPECT_TRUE(found) << spec.name << ": " << automatic.formulation << " + " << automatic.integrator << " ("
                           << automatic.formulation_reason << "; " << automatic.integrator_reason << ")";
        ++scenes;
    }
    EXPECT_GE(scenes, 10);
}

// A peer engine that is not installed is reported and skipped; the mbd runs still happen.
TEST(Bench, MissingPeerIsReportedNotFatal) {
    const auto dir = std::filesystem::temp_directory_path() / "mbd_test_bench_peer";
    const std::string scene = pendulum_bench_scene(
        dir, "  runs:\n    - {formulation: augmented, integrator: dopri5, tolerances: [1.0e-6]}\n"
             "  peers:\n    model: pendulum_a01\n    simbody: {tolerances: [1.0e-6]}\n"
             "    mujoco: {integrator: rk4, steps: [1.0e-3]}\n");
    BenchOptions options;
    options.repeat = 1;
    options.progress = false;
    options.peer_dirs = {(dir / "no-such-peers").string()};
    const BenchSceneResult result = run_bench_scene(scene, test::shared_registry(), options);
    ASSERT_EQ(result.rows.size(), 1u);
    EXPECT_EQ(result.rows[0].status, "ok");
    EXPECT_LT(result.rows[0].error, 1e-4);
    ASSERT_EQ(result.notes.size(), 2u);
    EXPECT_NE(result.notes[0].find("peer simbody: not installed"), std::string::npos) << result.notes[0];
    EXPECT_NE(result.notes[1].find("peer mujoco: not installed"), std::string::npos) << result.notes[1];

    // and through the command, which writes CSV and JSON
    const std::string csv = (dir / "b.csv").string(), json = (dir / "b.json").string();
    const auto r = test::run_mbd("bench " + scene + " --repeat 1 -q --peers " + options.peer_dirs[0] + " --csv " + csv +
                                 " --json " + json);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("not installed"), std::string::npos) << r.err;
    std::ifstream in(csv);
    std::string header, row;
    std::getline(in, header);
    std::getline(in, row);
    EXPECT_EQ(header.rfind("engine,scene,formulation,integrator,tolerance,step,cpu_s,steps,error,error_measure,reference_kind", 0), 0u);
    EXPECT_NE(row.find("closed_form"), std::string::npos) << row;
    std::filesystem::remove_all(dir);
}

// --min-tol leaves out the tighter tolerances of the peers too, and a missing peer's skipped
// runs are counted from the same grid: simbody (found, a fake program printing the bob at rest)
// runs 1e-6 but not 1e-8; mujoco (missing) has its one tolerance above the floor skipped.
TEST(Bench, MinimumToleranceAppliesToThePeersAndTheSkippedCount) {
    const auto dir = std::filesystem::temp_directory_path() / "mbd_test_bench_min_tol";
    std::filesystem::remove_all(dir);
    const std::string scene = pendulum_bench_scene(
        dir, "  runs:\n    - {formulation: augmented, integrator: dopri5, tolerances: [1.0e-5, 1.0e-9]}\n"
             "  peers:\n    model: pendulum_a01\n    simbody: {tolerances: [1.0e-6, 1.0e-8]}\n"
             "    mujoco: {tolerances: [1.0e-4, 1.0e-10]}\n");
    const auto peers = dir / "peers";
    std::filesystem::create_directories(peers);
    std::ofstream(peers / "mbd_peer_simbody") << "#!/bin/sh\necho '0.5 3'\necho '0.5 1 0 0'\necho '1 1 0 0'\n";
    std::filesystem::permissions(peers / "mbd_peer_simbody", std::filesystem::perms::owner_all);
    BenchOptions options;
    options.repeat = 1;
    options.progress = false;
    options.tolerance_floor = 1e-6;
    options.peer_dirs = {peers.string()};
    const BenchSceneResult result = run_bench_scene(scene, test::shared_registry(), options);
    ASSERT_EQ(result.rows.size(), 2u);  // augmented at 1e-5, simbody at 1e-6
    EXPECT_EQ(result.rows[0].engine, "mbd");
    EXPECT_EQ(result.rows[0].tolerance, 1e-5);
    EXPECT_EQ(result.rows[1].engine, "simbody");
    EXPECT_EQ(result.rows[1].tolerance, 1e-6);
    EXPECT_EQ(result.rows[1].status, "ok");
    EXPECT_EQ(result.rows[1].cpu_s, 0.5);
    EXPECT_EQ(result.skipped_peer_runs, 1);  // mujoco at 1e-4; 1e-10 is below the floor
    const BenchTally t = tally(result);
    EXPECT_EQ(t.ok, 2);
    EXPECT_EQ(t.runs(), 3);
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace mbd
