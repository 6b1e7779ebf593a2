// `mbd sweep` (issue 18, docs/sweep.md): the designs, a 200-case Latin hypercube of the pendulum
// run serially, in 2 threads and on 3 MPI ranks (identical tables, each case equal to its own
// `mbd simulate`), kills of the process, of a worker rank and of the master rank followed by
// --resume, a statics sweep of the slider crank against its closed form, and bad input.
#include <gtest/gtest.h>

#include <mbd/app/study.hpp>
#include <mbd/app/study_design.hpp>
#include <mbd/app/sweep_results.hpp>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include "support/sanitizer_build.hpp"
#include "support/test_support.hpp"

namespace {

namespace fs = std::filesystem;
using mbd::test::write_text;
using mbd::test::g17;
using mbd::test::run_command;
using mbd::test::run_mbd;
using mbd::test::scratch;

// Under AddressSanitizer the ranks run without the leak check: Open MPI's components, loaded and
// unloaded by MPI_Init and MPI_Finalize, leave allocations LeakSanitizer reports in modules it can
// no longer name. mbd's own leaks are checked by the serial and threaded runs of the same code.
const std::string kMpirun =
    "mpirun --allow-run-as-root --oversubscribe -x ASAN_OPTIONS=detect_leaks=0:intercept_tls_get_addr=0 ";

std::string pendulum_scene() { return mbd::test::scene_path("dynamics/pendulum-a01.yaml").string(); }

// The pendulum study: `cases` LHS cases over the length (the bob's x at the start) and the mass.
std::string pendulum_study(long cases, double t_end = 1.0) {
    std::ostringstream s;
    s << "scene: " << pendulum_scene() << "\n"
      << "analysis: {type: simulate, t_end: " << t_end << ", integrator: dopri5, tol: 1.0e-7, output_step: 0.01}\n"
      << "parameters:\n"
      << "  - {path: \"bodies.bob.position[0]\", distribution: uniform, range: [0.5, 1.5]}\n"
      << "  - {path: bodies.bob.mass, distribution: uniform, range: [0.5, 2.0]}\n"
      << "design: {type: latin_hypercube, cases: " << cases << ", seed: 7}\n"
      << "metrics:\n  - final: bob.x\n  - final: bob.y\n  - min: bob.y\n  - max: pivot.fy\n"
      << "series: [t, bob.x, pivot.fy]\n";
    return s.str();
}

// A CSV with text cells (the sweep table has status, failure and message columns).
struct Table {
    std::vector<std::string> header;
    std::vector<std::vector<std::string>> rows;
    int column(const std::string& name) const {
        for (size_t k = 0; k < header.size(); ++k)
            if (header[k] == name) return static_cast<int>(k);
        return -1;
    }
};

std::vector<std::string> split_csv(const std::string& line) {
    std::vector<std::string> out{""};
    bool quoted = false;
    for (size_t k = 0; k < line.size(); ++k) {
        const char c = line[k];
        if (quoted && c == '"' && k + 1 < line.size() && line[k + 1] == '"') out.back() += '"', ++k;
        else if (c == '"') quoted = !quoted;
        else if (c == ',' && !quoted) out.emplace_back();
        else out.back() += c;
    }
    return out;
}

Table read_table(const fs::path& path) {
    std::ifstream in(path);
    Table t;
    std::string line;
    std::getline(in, line);
    t.header = split_csv(line);
    while (std::getline(in, line)) t.rows.push_back(split_csv(line));
    return t;
}

// `mbd sweep STUDY` into DIR/r.h5 with its CSV table, which is returned (the run must succeed).
Table sweep_table(const fs::path& study, const fs::path& dir) {
    const auto r = run_mbd("sweep " + study.string() + " -q -o " + (dir / "r.h5").string() + " --csv " +
                           (dir / "r.csv").string());
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return read_table(dir / "r.csv");
}

// The parameter and metric cells of every row (cpu_s left out: it is a measurement).
std::vector<std::vector<std::string>> numbers(const Table& t) {
    const int last = t.column("cpu_s");
    std::vector<std::vector<std::string>> out;
    for (const auto& row : t.rows) out.emplace_back(row.begin(), row.begin() + last);
    return out;
}

// The finished rows of a sweep's output: its journal while it runs, else the HDF5 file.
std::map<long, mbd::SweepRow> stored_rows(const fs::path&, const fs::path& output) {
    return mbd::read_sweep_rows(output);
}

TEST(SweepDesign, LatinHypercubeHasOnePointPerStratumAndIsReproducible) {
    const fs::path dir = scratch("design");
    const fs::path study_file = write_text(dir / "lhs.yaml", pendulum_study(50));
    const mbd::Study study = mbd::read_study(study_file, mbd::test::shared_registry());
    const auto cases = mbd::design_cases(study);
    ASSERT_EQ(cases.size(), 50u);
    const double lo[2] = {0.5, 0.5}, hi[2] = {1.5, 2.0};
    for (int j = 0; j < 2; ++j) {
        std::set<long> strata;
        for (const auto& c : cases) {
            const double u = (c[j] - lo[j]) / (hi[j] - lo[j]);
            ASSERT_GT(u, 0.0);
            ASSERT_LT(u, 1.0);
            strata.insert(static_cast<long>(std::floor(u * 50)));
        }
        EXPECT_EQ(strata.size(), 50u) << "parameter " << j << ": every one of the 50 strata holds one point";
    }
    EXPECT_EQ(mbd::design_cases(study), cases);  // the same seed, the same design
}

TEST(SweepDesign, GridVariesTheLastParameterFastestAndMonteCarloNormalHasItsMoments) {
    const fs::path dir = scratch("design-grid");
    const fs::path grid = write_text(dir / "grid.yaml",
                                "scene: " + pendulum_scene() +
                                    "\nanalysis: {type: simulate, t_end: 0.1}\nparameters:\n"
                                    "  - {path: bodies.bob.mass, values: [1, 2]}\n"
                                    "  - {path: \"gravity[1]\", range: [-10, -9], count: 3}\n"
                                    "design: {type: grid}\nmetrics: [{final: bob.x}]\n");
    const mbd::Study g = mbd::read_study(grid, mbd::test::shared_registry());
    const std::vector<std::vector<double>> expected{{1, -10}, {1, -9.5}, {1, -9}, {2, -10}, {2, -9.5}, {2, -9}};
    EXPECT_EQ(mbd::design_cases(g), expected);

    const fs::path mc = write_text(dir / "mc.yaml", "scene: " + pendulum_scene() +
                                                   "\nanalysis: {type: simulate, t_end: 0.1}\nparameters:\n"
                                                   "  - {path: bodies.bob.mass, distribution: normal, mean: 2, sd: 0.1}\n"
                                                   "design: {type: monte_carlo, cases: 20000, seed: 3}\n"
                                                   "metrics: [{final: bob.x}]\n");
    const mbd::Study m = mbd::read_study(mc, mbd::test::shared_registry());
    double sum = 0, squares = 0;
    const auto cases = mbd::design_cases(m);
    for (const auto& c : cases) sum += c[0];
    const double mean = sum / cases.size();
    for (const auto& c : cases) squares += (c[0] - mean) * (c[0] - mean);
    const double sd = std::sqrt(squares / (cases.size() - 1));
    EXPECT_NEAR(mean, 2.0, 4 * 0.1 / std::sqrt(20000.0));   // 4 standard errors
    EXPECT_NEAR(sd, 0.1, 4 * 0.1 / std::sqrt(2 * 20000.0));
}

// Lognormal (mu, sigma of the logarithm) and triangular (lower, mode, upper) draws: their
// moments within 4 standard errors, the triangular ones inside their bounds.
TEST(SweepDesign, LognormalAndTriangularDrawsHaveTheirMoments) {
    const fs::path dir = scratch("design-distributions");
    const fs::path file = write_text(dir / "mc.yaml",
                                "scene: " + pendulum_scene() +
                                    "\nanalysis: {type: simulate, t_end: 0.1}\nparameters:\n"
                                    "  - {path: bodies.bob.mass, distribution: lognormal, mu: 0.5, sigma: 0.2}\n"
                                    "  - {path: \"gravity[1]\", distribution: triangular, lower: -10, mode: -9.5, "
                                    "upper: -8}\n"
                                    "design: {type: monte_carlo, cases: 20000, seed: 5}\nmetrics: [{final: bob.x}]\n");
    const auto cases = mbd::design_cases(mbd::read_study(file, mbd::test::shared_registry()));
    ASSERT_EQ(cases.size(), 20000u);
    const double n = static_cast<double>(cases.size());
    auto moments = [&](auto value) {
        double sum = 0, squares = 0;
        for (const auto& c : cases) sum += value(c);
        const double mean = sum / n;
        for (const auto& c : cases) squares += (value(c) - mean) * (value(c) - mean);
        return std::pair<double, double>{mean, std::sqrt(squares / (n - 1))};
    };
    const auto [log_mean, log_sd] = moments([](const std::vector<double>& c) { return std::log(c[0]); });
    EXPECT_NEAR(log_mean, 0.5, 4 * 0.2 / std::sqrt(n));
    EXPECT_NEAR(log_sd, 0.2, 4 * 0.2 / std::sqrt(2 * n));
    const double a = -10, c = -9.5, b = -8;
    const double mean = (a + b + c) / 3, sd = std::sqrt((a * a + b * b + c * c - a * b - a * c - b * c) / 18);
    const auto [tri_mean, tri_sd] = moments([](const std::vector<double>& x) { return x[1]; });
    EXPECT_NEAR(tri_mean, mean, 4 * sd / std::sqrt(n));
    EXPECT_NEAR(tri_sd, sd, 4 * sd / std::sqrt(2 * n));
    for (const auto& x : cases) {
        EXPECT_GE(x[1], a);
        EXPECT_LE(x[1], b);
    }
}

// The acceptance test: serial, 2 threads and 3 MPI ranks give the same table, and every case
// is the `mbd simulate` of its own scene (the values written into the file) to 1e-12. 200 cases;
// 50 in the sanitizer build, where each case and each `mbd simulate` process is some 20 times
// slower (still 25 cases per MPI worker, the threads and ranks taking cases as they free up).
TEST(SweepCli, PendulumLhsSerialThreadsAndMpiAgreeWithSingleSimulations) {
    const long count = mbd::test::kSanitizerBuild ? 50 : 200;
    const fs::path dir = scratch("lhs");
    const fs::path study = write_text(dir / "study.yaml", pendulum_study(count));
    const std::string base = "sweep " + study.string() + " -q -o ";
    auto r = run_mbd(base + (dir / "serial.h5").string() + " --csv " + (dir / "serial.csv").string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r = run_mbd(base + (dir / "threads.h5").string() + " --threads 2 --csv " + (dir / "threads.csv").string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r = run_command(kMpirun + "-np 3 " + std::string(MBD_EXECUTABLE) + " " + base + (dir / "mpi.h5").string() + " --csv " +
                    (dir / "mpi.csv").string());
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;

    const Table serial = read_table(dir / "serial.csv");
    ASSERT_EQ(serial.rows.size(), static_cast<size_t>(count));
    EXPECT_EQ(numbers(read_table(dir / "threads.csv")), numbers(serial));
    EXPECT_EQ(numbers(read_table(dir / "mpi.csv")), numbers(serial));
    // the HDF5 table holds the same numbers
    const auto stored = stored_rows(study, dir / "mpi.h5");
    ASSERT_EQ(stored.size(), static_cast<size_t>(count));
    for (const auto& row : serial.rows)
        EXPECT_EQ(g17(stored.at(std::stol(row[0])).result.metrics[0]), row[serial.column("final(bob.x)")]);

    // every case, run as its own scene written here by hand (not through the sweep's parameter paths)
    for (size_t k = 0; k < serial.rows.size(); ++k) {
        const auto& row = serial.rows[k];
        const double L = std::stod(row[1]), m = std::stod(row[2]);
        const fs::path scene = write_text(dir / "case.yaml", "dimension: planar\ngravity: [0, -9.81]\nbodies:\n"
                                                        "  - {name: bob, mass: " + g17(m) +
                                                            ", inertia: 1.0e-6, position: [" + g17(L) +
                                                            ", 0.0], angle: 0.0}\njoints:\n  - {name: pivot, type: "
                                                            "revolute, bodies: [ground, bob], point: [0.0, 0.0]}\n");
        const fs::path out = dir / "case.csv";
        r = run_mbd("simulate " + scene.string() + " --t-end 1 --integrator dopri5 --tol 1e-7 --output-step 0.01 "
                                                   "--reactions -q -o " + out.string());
        ASSERT_EQ(r.exit_code, 0) << r.err;
        const mbd::test::Csv csv = mbd::test::read_csv(out);
        const int x = csv.column("bob.x"), y = csv.column("bob.y"), fy = csv.column("pivot.fy");
        double min_y = INFINITY, max_fy = -INFINITY;
        for (const auto& line : csv.rows) min_y = std::min(min_y, line[y]), max_fy = std::max(max_fy, line[fy]);
        SCOPED_TRACE("case " + row[0]);
        EXPECT_NEAR(std::stod(row[3]), csv.rows.back()[x], 1e-12);
        EXPECT_NEAR(std::stod(row[4]), csv.rows.back()[y], 1e-12);
        EXPECT_NEAR(std::stod(row[5]), min_y, 1e-12);
        EXPECT_NEAR(std::stod(row[6]), max_fy, 1e-12);
        // the case's time series in the HDF5 file: the same rows as the simulation's CSV
        const mbd::CaseResult& kept = stored.at(std::stol(row[0])).result;
        ASSERT_EQ(kept.series_rows, static_cast<long>(csv.rows.size()));
        const int columns[3] = {csv.column("t"), x, fy};
        for (size_t i = 0; i < csv.rows.size(); ++i)
            for (int c = 0; c < 3; ++c) ASSERT_NEAR(kept.series[3 * i + c], csv.rows[i][columns[c]], 1e-12) << "row " << i;
    }
}

// ---- kills and --resume

pid_t spawn(const std::string& command) {
    const pid_t pid = fork();
    if (pid == 0) {
        setpgid(0, 0);
        execl("/bin/sh", "sh", "-c", ("exec " + command + " > /dev/null 2>&1").c_str(), static_cast<char*>(nullptr));
        _exit(127);
    }
    return pid;
}

// Waits until the results file holds at least `rows` finished cases (read as --resume reads it).
// The limit is wall time, generous for a loaded CI machine: the test fails only if it passes.
long wait_for_rows(const fs::path& study, const fs::path& output, long rows, pid_t child) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(3);
    while (std::chrono::steady_clock::now() < deadline) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        if (fs::exists(output.string() + ".partial")) {
            const long n = static_cast<long>(stored_rows(study, output).size());
            if (n >= rows) return n;
        }
        int status = 0;
        if (waitpid(child, &status, WNOHANG) == child) return -1;  // ended before: the test fails
    }
    return -1;
}

// The process of MPI rank `rank` among the descendants of `root` (its environment says).
pid_t rank_process(pid_t root, int rank) {
    for (int attempt = 0; attempt < 200; ++attempt) {
        for (const auto& entry : fs::directory_iterator("/proc")) {
            const std::string name = entry.path().filename();
            if (name.find_first_not_of("0123456789") != std::string::npos) continue;
            std::ifstream environ(entry.path() / "environ");
            std::string text((std::istreambuf_iterator<char>(environ)), std::istreambuf_iterator<char>());
            if (text.find(std::string("OMPI_COMM_WORLD_RANK=") + std::to_string(rank) + '\0') == std::string::npos)
                continue;
            // the whole entry (NUL-terminated): root 123 must not match a test of root 1234 beside it
            if (text.find("MBD_SWEEP_TEST=" + std::to_string(root) + '\0') != std::string::npos) return std::stoi(name);
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return -1;
}

// How many cases of pendulum_study(n, t_end) one sweep runs in about `seconds` on this build
// and machine (a sanitizer build is some 30 times slower than Release), within [fewest, most]:
// the tests that must catch a sweep while it runs size it by its measured pace, not by a guess.
// (A ceiling of 600 cases let a faster engine finish the kill test's sweep, on two MPI workers,
// before its first third could be seen: the ceilings are now 6000.) The pace is measured on
// sweeps of 10 and 40 cases, or of 3 and 12 in the sanitizer build, where a case of 8 to 20 s
// takes a fifth to a half of a second of processor time (docs/ci.md, "Third pass").
long cases_lasting(double seconds, double t_end, long fewest, long most) {
    auto timed = [t_end](long n) {
        const fs::path dir = scratch("pace-" + std::to_string(n));
        const fs::path study = write_text(dir / "study.yaml", pendulum_study(n, t_end));
        const auto start = std::chrono::steady_clock::now();
        EXPECT_EQ(run_mbd("sweep " + study.string() + " -q -o " + (dir / "r.h5").string()).exit_code, 0);
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };
    // start-up cancels in the difference; a quarter of the larger run's average bounds it from below
    // should a load spike on the machine shorten the larger run
    const long probe = mbd::test::kSanitizerBuild ? 3 : 10;
    const double t_small = timed(probe), t_large = timed(4 * probe);
    const double per_case = std::max((t_large - t_small) / (3.0 * probe), t_large / (16.0 * probe));
    return std::clamp(std::lround(seconds / per_case), fewest, most);
}

// Kill the sweep (`rank` < 0: the serial process; else that MPI rank) with SIGKILL once a
// tenth of it is recorded, resume, and compare with an uninterrupted run. (At a third, an MPI
// sweep once ran to its end before the kill: OUTPUT.partial lags the cases finished by up to
// ten of its own write times, and three ranks on a machine that a parallel test just left run
// faster than the pace measured while it was busy.)
// At least 90 cases (40 in the sanitizer build, whose cases last some 30 times longer: the kill
// still comes at a tenth, seconds before the end).
void kill_and_resume(const std::string& name, int rank) {
    const fs::path dir = scratch(name);
    const long cases = cases_lasting(6.0, 8.0, mbd::test::kSanitizerBuild ? 40 : 90, 6000);
    const fs::path study = write_text(dir / "study.yaml", pendulum_study(cases, 8.0));
    const fs::path output = dir / "killed.h5";
    const std::string sweep = " sweep " + study.string() + " -q --flush-seconds 0.02 -o " + output.string();
    const std::string tag = "MBD_SWEEP_TEST=" + std::to_string(getpid());
    const pid_t child = spawn(rank < 0 ? std::string(MBD_EXECUTABLE) + sweep
                                       : "env " + tag + " " + kMpirun + "-x MBD_SWEEP_TEST -np 3 " + MBD_EXECUTABLE +
                                             sweep);
    ASSERT_GT(child, 0);
    const long before = wait_for_rows(study, output, cases / 10, child);
    ASSERT_GT(before, 0) << "the sweep ended or wrote nothing before it could be killed";
    ASSERT_LT(before, cases) << "the sweep finished before it could be killed";
    const pid_t victim = rank < 0 ? child : rank_process(getpid(), rank);
    ASSERT_GT(victim, 0) << "no process of rank " << rank;
    ASSERT_EQ(kill(victim, SIGKILL), 0);
    int status = 0;
    waitpid(child, &status, 0);
    EXPECT_FALSE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "a killed sweep does not end as a success";
    ASSERT_FALSE(fs::exists(output)) << "an unfinished study has no file under its final name";
    const long kept = static_cast<long>(stored_rows(study, output).size());
    EXPECT_GE(kept, before);
    EXPECT_LT(kept, cases);

    const auto resumed = rank < 0 ? run_mbd(sweep.substr(1) + " --resume")
                                  : run_command(kMpirun + "-np 3 " + MBD_EXECUTABLE + sweep + " --resume");
    ASSERT_EQ(resumed.exit_code, 0) << resumed.out << resumed.err;
    ASSERT_TRUE(fs::exists(output));
    const auto rows = stored_rows(study, output);
    ASSERT_EQ(rows.size(), static_cast<size_t>(cases));  // a map by case: every case exactly once
    long index = 0;
    for (const auto& [k, row] : rows) EXPECT_EQ(k, index++);

    const fs::path reference = dir / "reference.h5";
    ASSERT_EQ(run_mbd("sweep " + study.string() + " -q --threads 2 -o " + reference.string()).exit_code, 0);
    const auto expected = stored_rows(study, reference);
    for (const auto& [k, row] : rows) {
        EXPECT_EQ(row.values, expected.at(k).values) << "case " << k;
        EXPECT_EQ(row.result.metrics, expected.at(k).result.metrics) << "case " << k;
    }
}

TEST(SweepResume, ProcessKilledHalfwayThenResumedRunsEveryCaseOnce) { kill_and_resume("kill-serial", -1); }
TEST(SweepResume, MpiWorkerKilledHalfwayThenResumedRunsEveryCaseOnce) { kill_and_resume("kill-worker", 1); }
TEST(SweepResume, MpiMasterKilledHalfwayThenResumedRunsEveryCaseOnce) { kill_and_resume("kill-master", 0); }

// A serial run records its cases in order, so a kill leaves a prefix; the MPI ranks leave gaps.
// Here a results file with gaps (cases 1, 2, 5, 6, 7 and 10 of 12 finished, their rows those of
// an uninterrupted run but for a CPU time no run gives, so that a row run again shows) is resumed
// by one process: every case is then present once, the kept rows are kept (not run again) and
// every row equals the uninterrupted run's.
TEST(SweepResume, SerialResumeFillsEveryGapOnce) {
    const fs::path dir = scratch("gaps");
    const fs::path study_file = write_text(dir / "study.yaml", pendulum_study(12));
    const fs::path fresh = dir / "fresh.h5", output = dir / "gaps.h5";
    ASSERT_EQ(run_mbd("sweep " + study_file.string() + " -q -o " + fresh.string()).exit_code, 0);
    const auto expected = stored_rows(study_file, fresh);
    ASSERT_EQ(expected.size(), 12u);
    const std::set<long> kept = {1, 2, 5, 6, 7, 10};
    {
        const mbd::Study study = mbd::read_study(study_file, mbd::test::shared_registry());
        const mbd::CaseDesign design(study);
        // the inputs --resume checks: the study file and its scene (which has no `base:` files)
        mbd::SweepResults partial = mbd::SweepResults::create(output, study, design,
                                                              mbd::fingerprint_inputs({study.file, study.scene}));
        for (long k : kept) {
            mbd::CaseResult row = expected.at(k).result;
            row.cpu_seconds = 1000.0 + k;
            partial.add(k, row);
        }
        partial.flush(true);
    }
    ASSERT_FALSE(fs::exists(output));
    ASSERT_EQ(stored_rows(study_file, output).size(), kept.size());
    const auto resumed = run_mbd("sweep " + study_file.string() + " -q -o " + output.string() + " --resume");
    ASSERT_EQ(resumed.exit_code, 0) << resumed.out << resumed.err;
    ASSERT_TRUE(fs::exists(output));
    const auto rows = stored_rows(study_file, output);
    ASSERT_EQ(rows.size(), 12u);  // a map by case: every case exactly once
    long index = 0;
    for (const auto& [k, row] : rows) {
        EXPECT_EQ(k, index++);
        EXPECT_EQ(row.values, expected.at(k).values) << "case " << k;
        EXPECT_EQ(row.result.metrics, expected.at(k).result.metrics) << "case " << k;
        EXPECT_EQ(row.result.series, expected.at(k).result.series) << "case " << k;
        if (kept.count(k))
            EXPECT_EQ(row.result.cpu_seconds, 1000.0 + k) << "case " << k << " was run again";
        else
            EXPECT_LT(row.result.cpu_seconds, 1000.0) << "case " << k;
    }
}

TEST(SweepResume, RefusesToOverwriteUnfinishedResultsWithoutResume) {
    const fs::path dir = scratch("refuse-partial");
    const fs::path study = write_text(dir / "study.yaml", pendulum_study(4));
    write_text(dir / "r.h5.partial", "x");
    const auto r = run_mbd("sweep " + study.string() + " -q -o " + (dir / "r.h5").string());
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("--resume"), std::string::npos) << r.err;
    EXPECT_EQ(mbd::test::read_text(dir / "r.h5.partial"), "x");
}

// ---- statics: the slider crank under a crank torque M and a pull F on the slider (no
// gravity). Virtual work, M d(theta) + F d(x_B) = 0 with x_B = l2 cos(theta) + sqrt(l3^2 -
// l2^2 sin^2(theta)), gives M = F l2 sin(theta) (1 + l2 cos(theta) / sqrt(l3^2 - l2^2 sin^2(theta))).
TEST(SweepCli, SliderCrankStaticsOverTheCrankTorqueFollowTheClosedForm) {
    const double l2 = 0.2, l3 = 0.5, F = 20.0, th0 = 0.5;
    auto torque = [&](double th) {
        const double s = std::sin(th), c = std::cos(th);
        return F * l2 * s * (1 + l2 * c / std::sqrt(l3 * l3 - l2 * l2 * s * s));
    };
    const double th3 = std::asin(-l2 / l3 * std::sin(th0));
    const double Ax = l2 * std::cos(th0), Ay = l2 * std::sin(th0), Bx = Ax + l3 * std::cos(th3);
    const fs::path dir = scratch("slider-crank");
    std::ostringstream scene;
    scene << "dimension: planar\ngravity: [0, 0]\nbodies:\n"
          << "  - {name: crank, mass: 1, inertia: 0.01, position: [" << g17(Ax / 2) << ", " << g17(Ay / 2)
          << "], angle: " << g17(th0) << "}\n"
          << "  - {name: rod, mass: 1, inertia: 0.02, position: [" << g17((Ax + Bx) / 2) << ", " << g17(Ay / 2)
          << "], angle: " << g17(th3) << "}\n"
          << "  - {name: slider, mass: 1, inertia: 0.001, position: [" << g17(Bx) << ", 0]}\n"
          << "joints:\n"
          << "  - {name: O, type: revolute, bodies: [ground, crank], point: [0, 0]}\n"
          << "  - {name: A, type: revolute, bodies: [crank, rod], point: [" << g17(Ax) << ", " << g17(Ay) << "]}\n"
          << "  - {name: B, type: revolute, bodies: [rod, slider], point: [" << g17(Bx) << ", 0]}\n"
          << "  - {name: guide, type: prismatic, bodies: [ground, slider], point: [0, 0], axis: [1, 0]}\n"
          << "forces:\n"
          << "  - {name: motor, type: point_torque, body: crank, torque: 1}\n"
          << "  - {name: pull, type: point_force, body: slider, force: [" << F << ", 0]}\n";
    write_text(dir / "slider-crank.yaml", scene.str());
    const fs::path study = write_text(dir / "study.yaml",
                                 "scene: slider-crank.yaml\nanalysis: {type: statics, tolerance: 1.0e-12}\n"
                                 "parameters:\n  - {path: forces.motor.torque, range: [0.2, 3.0], count: 8}\n"
                                 "design: {type: grid}\nmetrics:\n  - final: crank.angle\n  - final: O.coordinate\n");
    const Table t = sweep_table(study, dir);
    ASSERT_EQ(t.rows.size(), 8u);
    for (const auto& row : t.rows) {
        ASSERT_EQ(row[t.column("status")], "ok") << row[t.column("message")];
        const double M = std::stod(row[1]), angle = std::stod(row[t.column("final(crank.angle)")]);
        // the closed form's root on the stable branch (below the peak of M(theta) near pi/2), by bisection
        double lo = 0.0, hi = 1.5;
        for (int k = 0; k < 200; ++k) (torque(0.5 * (lo + hi)) < M ? lo : hi) = 0.5 * (lo + hi);
        EXPECT_NEAR(angle, 0.5 * (lo + hi), 1e-8) << "M = " << M;
        EXPECT_NEAR(torque(angle), M, 1e-8);
        EXPECT_NEAR(std::stod(row[t.column("final(O.coordinate)")]), angle, 1e-8);
    }
}

// ---- inverse: a rod driven about a pin, theta = -0.4 + 0.3 sin(2 t), for three masses (its
// inertia about the centre kept at 1/12): tau = (I + m l^2) theta'' + m g l cos(theta), l = 0.5.
TEST(SweepCli, InverseSweepOverTheRodMassFollowsTheClosedForm) {
    const fs::path dir = scratch("inverse");
    write_text(dir / "arm.yaml", "dimension: planar\ngravity: [0, -9.81]\nbodies:\n"
                            "  - {name: rod, mass: 1, inertia: 0.08333333333333333, "
                            "position: [0.46053049700144255, -0.19470917115432526], angle: -0.4}\n"
                            "joints:\n  - {name: pin, type: revolute, bodies: [ground, rod], point: [0, 0]}\n"
                            "drivers:\n  - {name: swing, joint: pin, motion: {type: harmonic, offset: -0.4, "
                            "amplitude: 0.3, frequency: 2}}\n"
                            "actuators:\n  - {name: motor, joint: pin}\n");
    const fs::path study = write_text(dir / "study.yaml",
                                 "scene: arm.yaml\nanalysis: {type: inverse, t_end: 1, step: 0.01}\n"
                                 "parameters:\n  - {path: bodies.rod.mass, values: [0.5, 1, 2]}\n"
                                 "design: {type: grid}\nmetrics:\n  - final: motor\n  - max: motor\n  - min: motor\n");
    const Table t = sweep_table(study, dir);
    ASSERT_EQ(t.rows.size(), 3u);
    for (const auto& row : t.rows) {
        ASSERT_EQ(row[t.column("status")], "ok") << row[t.column("message")];
        const double m = std::stod(row[1]), l = 0.5, g = 9.81, I = 1.0 / 12;
        auto tau = [&](double time) {
            const double theta = -0.4 + 0.3 * std::sin(2 * time), acceleration = -1.2 * std::sin(2 * time);
            return (I + m * l * l) * acceleration + m * g * l * std::cos(theta);
        };
        double most = -INFINITY, least = INFINITY;
        for (int k = 0; k <= 100; ++k) most = std::max(most, tau(0.01 * k)), least = std::min(least, tau(0.01 * k));
        EXPECT_NEAR(std::stod(row[t.column("final(motor)")]), tau(1.0), 1e-9) << "m = " << m;
        EXPECT_NEAR(std::stod(row[t.column("max(motor)")]), most, 1e-9);
        EXPECT_NEAR(std::stod(row[t.column("min(motor)")]), least, 1e-9);
    }
}

// On a terminal (script(1) gives a pseudo-terminal) a sweep of a few seconds draws its progress
// bar: cases done of all, elapsed time and time left, each redraw clearing its line.
TEST(SweepCli, ATerminalShowsTheProgressBarWithTheTimeLeft) {
    const fs::path dir = scratch("progress");
    // at least 60 cases, or 15 in the sanitizer build: some 8 s of redraws there
    const long cases = cases_lasting(3.0, 20.0, mbd::test::kSanitizerBuild ? 15 : 60, 6000);
    const fs::path study = write_text(dir / "study.yaml", pendulum_study(cases, 20.0));
    const fs::path log = dir / "terminal.txt";
    const auto r = run_command("script -qec 'env COLUMNS=100 " + std::string(MBD_EXECUTABLE) + " sweep " + study.string() + " -o " +
                               (dir / "r.h5").string() + "' " + log.string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string text = mbd::test::read_text(log);
    EXPECT_NE(text.find("\r\033[K"), std::string::npos) << "no redraw in a sweep of several seconds";
    EXPECT_NE(text.find(" / " + std::to_string(cases) + " cases"), std::string::npos) << text.substr(0, 400);
    EXPECT_NE(text.find("left"), std::string::npos) << text.substr(0, 400);
    EXPECT_NE(text.find("elapsed"), std::string::npos) << text.substr(0, 400);
}

// ---- bad input

TEST(SweepCli, UnknownParameterPathNamesTheKeyAndNearMatches) {
    const fs::path dir = scratch("bad-path");
    std::string text = pendulum_study(4);
    text.replace(text.find("bodies.bob.mass"), 15, "bodies.bob.mas");
    const fs::path study = write_text(dir / "study.yaml", text);
    const auto r = run_mbd("sweep " + study.string() + " -o " + (dir / "r.h5").string());
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find(study.string() + ":5"), std::string::npos) << r.err;  // the study file and line
    EXPECT_NE(r.err.find("bodies.bob.mas"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("did you mean 'mass'"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "r.h5.partial"));
}

TEST(SweepCli, UnknownMetricColumnIsRefusedWithNearMatches) {
    const fs::path dir = scratch("bad-metric");
    std::string text = pendulum_study(4);
    text.replace(text.find("max: pivot.fy"), 13, "max: pivot.fz");
    const fs::path study = write_text(dir / "study.yaml", text);
    const auto r = run_mbd("sweep " + study.string() + " -o " + (dir / "r.h5").string());
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("no column 'pivot.fz'"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("did you mean"), std::string::npos) << r.err;
}

TEST(SweepCli, NegativeMassGivesFailedCasesWithTheMessage) {
    const fs::path dir = scratch("negative-mass");
    const fs::path study = write_text(dir / "study.yaml", "scene: " + pendulum_scene() +
                                                         "\nanalysis: {type: simulate, t_end: 0.2}\nparameters:\n"
                                                         "  - {path: bodies.bob.mass, values: [-1, 1, -2]}\n"
                                                         "design: {type: grid}\nmetrics: [{final: bob.y}]\n");
    const Table t = sweep_table(study, dir);
    ASSERT_EQ(t.rows.size(), 3u);
    for (int k : {0, 2}) {
        EXPECT_EQ(t.rows[k][t.column("status")], "failed");
        EXPECT_EQ(t.rows[k][t.column("failure")], "scene");
        EXPECT_NE(t.rows[k][t.column("message")].find("mass"), std::string::npos) << t.rows[k][t.column("message")];
        EXPECT_EQ(t.rows[k][t.column("final(bob.y)")], "");  // no number for a failed case
    }
    EXPECT_EQ(t.rows[1][t.column("status")], "ok");
    const auto stored = stored_rows(study, dir / "r.h5");
    EXPECT_FALSE(stored.at(0).result.ok);
    EXPECT_NE(stored.at(0).result.message.find("mass"), std::string::npos);
}

TEST(SweepCli, UnwritableOutputIsRefusedBeforeAnyCaseRuns) {
    const fs::path dir = scratch("unwritable");
    const fs::path study = write_text(dir / "study.yaml", pendulum_study(4));
    auto r = run_mbd("sweep " + study.string() + " -o " + (dir / "missing" / "r.h5").string());
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("does not exist"), std::string::npos) << r.err;
    r = run_mbd("sweep " + study.string() + " -o " + dir.string());
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("is a folder"), std::string::npos) << r.err;
    r = run_mbd("sweep " + study.string() + " -o " + study.string());
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("is the input file"), std::string::npos) << r.err;
    EXPECT_EQ(r.out, "");  // nothing ran
}

}  // namespace

namespace {

// Modes about the statics: the pendulum hangs at the bottom and swings at
// omega = sqrt(m g L / (J + m L^2)) (J = 1e-6 kg m^2 about the bob's centre).
TEST(SweepCli, PendulumModesOverTheLengthFollowTheCompoundPendulumFrequency) {
    const fs::path dir = scratch("modes");
    const fs::path study = write_text(dir / "study.yaml", "scene: " + pendulum_scene() +
                                                         "\nanalysis: {type: modes}\nparameters:\n"
                                                         "  - {path: \"bodies.bob.position[0]\", values: [0.5, 1, 2]}\n"
                                                         "design: {type: grid}\n"
                                                         "metrics: [{final: mode1.natural_frequency}]\n");
    const Table t = sweep_table(study, dir);
    ASSERT_EQ(t.rows.size(), 3u);
    for (const auto& row : t.rows) {
        ASSERT_EQ(row[t.column("status")], "ok") << row[t.column("message")];
        const double L = std::stod(row[1]), m = 1.0, g = 9.81, J = 1e-6;
        EXPECT_NEAR(std::stod(row[2]), std::sqrt(m * g * L / (J + m * L * L)), 1e-6) << "L = " << L;
    }
}

}  // namespace
