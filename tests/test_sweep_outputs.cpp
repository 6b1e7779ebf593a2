// `mbd sweep`'s output files (issue 42): a device named as the output is never replaced (and
// `simulate --output` writes it in place), two sweeps on one output cannot both run, --resume
// refuses inputs whose content changed (the base scene, a `base:` file), the memory of a sweep
// does not grow with its case count, and an analysis option that would fail every case is
// refused before any case runs. Each test runs a few cases at most: the slow sweep tests are in
// test_sweep.cpp.
#include <gtest/gtest.h>

#include <mbd/app/input_fingerprint.hpp>
#include <mbd/app/study.hpp>
#include <mbd/app/study_design.hpp>
#include <mbd/app/sweep_results.hpp>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include <malloc.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include "support/child_process.hpp"
#include "support/sanitizer_build.hpp"
#include "support/test_support.hpp"

// Under AddressSanitizer (the CI's second run) freed blocks wait in a quarantine of 256 MB by
// default, which would count as this process's memory in the measurements below: keep it small.
// (Ignored without the sanitizer; ASAN_OPTIONS still overrides it.)
extern "C" const char* __asan_default_options() { return "quarantine_size_mb=1"; }

namespace {

namespace fs = std::filesystem;
using mbd::test::write_text;
using mbd::test::read_text;
using mbd::test::run_mbd;
using mbd::test::scratch;
using mbd::test::spawn_quiet;
using mbd::test::wait_until;

std::string pendulum_scene() { return mbd::test::scene_path("dynamics/pendulum-a01.yaml").string(); }

// A Monte Carlo study of the pendulum over the bob's mass, `cases` cases of `t_end` seconds.
std::string pendulum_study(const std::string& scene, long cases, double t_end = 0.1,
                           const std::string& design = "monte_carlo") {
    std::ostringstream s;
    s << "scene: " << scene << "\n"
      << "analysis: {type: simulate, t_end: " << t_end << ", integrator: dopri5, tol: 1.0e-6, output_step: 0.05}\n"
      << "parameters:\n  - {path: bodies.bob.mass, distribution: uniform, range: [0.5, 2.0]}\n"
      << "design: {type: " << design << ", cases: " << cases << ", seed: 3}\n"
      << "metrics:\n  - final: bob.x\n";
    return s.str();
}

bool is_character_device(const fs::path& path) {
    struct stat st {};
    return ::lstat(path.c_str(), &st) == 0 && S_ISCHR(st.st_mode);
}

// A character device like /dev/null (1, 3) in `dir`: never the real /dev.
fs::path make_null_device(const fs::path& dir) {
    const fs::path device = dir / "null";
    EXPECT_EQ(::mknod(device.c_str(), S_IFCHR | 0666, makedev(1, 3)), 0) << "mknod (the tests run as root)";
    EXPECT_TRUE(is_character_device(device));
    return device;
}

// Starts `command` (a shell command line, exec'd so that the pid is the program's).
// ---- devices

TEST(SweepOutputs, DeviceNamedAsOutputIsNeverReplaced) {
    const fs::path dir = scratch("device");
    const fs::path device = make_null_device(dir);
    const fs::path study = write_text(dir / "study.yaml", pendulum_study(pendulum_scene(), 2));

    // the HDF5 results are written beside the output and renamed: refused for a device
    auto r = run_mbd("sweep " + study.string() + " -q -o " + device.string());
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("not a regular file"), std::string::npos) << r.err;
    EXPECT_TRUE(is_character_device(device)) << "the device was replaced";
    EXPECT_FALSE(fs::exists(device.string() + ".partial"));
    EXPECT_FALSE(fs::exists(device.string() + ".lock"));

    // the CSV table is written in place on a device, as every command's CSV output
    r = run_mbd("sweep " + study.string() + " -q -o " + (dir / "r.h5").string() + " --csv " + device.string());
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(is_character_device(device));
    EXPECT_TRUE(fs::exists(dir / "r.h5"));
    EXPECT_FALSE(fs::exists(device.string() + ".partial"));

    r = run_mbd("simulate " + pendulum_scene() + " --t-end 0.05 -q --output " + device.string());
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(is_character_device(device)) << "simulate replaced the device";
    EXPECT_FALSE(fs::exists(device.string() + ".partial"));
}

// ---- the lock

// A sweep that lasts seconds holds the output's lock; a second study started on the same
// output once the lock is taken refuses at its start naming the first run's process, and
// leaves the first run's journal alone.
TEST(SweepOutputs, SecondSweepOnTheSameOutputRefusesAtStart) {
    const fs::path dir = scratch("lock");
    const fs::path first = write_text(dir / "first.yaml", pendulum_study(pendulum_scene(), 100000, 2.0));
    const fs::path second = write_text(dir / "second.yaml", pendulum_study(pendulum_scene(), 3, 0.1));
    const fs::path output = dir / "r.h5", lock = dir / "r.h5.lock";
    const pid_t running = spawn_quiet(std::string(MBD_EXECUTABLE) + " sweep " + first.string() + " -q -o " + output.string());
    ASSERT_GT(running, 0);
    ASSERT_TRUE(wait_until([&] { return fs::exists(lock) && !read_text(lock).empty(); }, running))
        << "the first sweep never took its lock";

    const auto r = run_mbd("sweep " + second.string() + " -q -o " + output.string());
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("is being written by another run"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("process " + std::to_string(running)), std::string::npos) << r.err;

    ASSERT_EQ(kill(running, SIGINT), 0);
    int status = 0;
    ASSERT_EQ(waitpid(running, &status, 0), running);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 130) << "status " << status;
    EXPECT_FALSE(fs::exists(output)) << "neither study is complete";
    EXPECT_FALSE(fs::exists(lock)) << "the first run removes its lock when it ends";
    // the journal is the first study's: --resume with it is accepted, with the second refused
    const auto wrong = run_mbd("sweep " + second.string() + " -q --resume -o " + output.string());
    EXPECT_EQ(wrong.exit_code, 2);
    EXPECT_NE(wrong.err.find("another study"), std::string::npos) << wrong.err;
}

// ---- --resume and the inputs' content

// A journal of `study` with no case yet, as a run stopped at once leaves it.
void start_journal(const fs::path& study_file, const fs::path& output) {
    const mbd::Study study = mbd::read_study(study_file, mbd::test::shared_registry());
    std::vector<fs::path> inputs{study.file, study.scene};
    for (const std::string& base : study.model->base_files) inputs.emplace_back(base);
    mbd::SweepResults::create(output, study, mbd::CaseDesign(study), mbd::fingerprint_inputs(inputs));
}

TEST(SweepOutputs, ResumeRefusesWhenTheSceneOrItsBaseChanged) {
    const fs::path dir = scratch("resume-inputs");
    write_text(dir / "base.yaml", read_text(pendulum_scene()));
    const fs::path scene = write_text(dir / "scene.yaml", "base: base.yaml\nname: derived\n");
    const fs::path study = write_text(dir / "study.yaml", pendulum_study(scene.string(), 4));
    const fs::path output = dir / "r.h5";
    const std::string resume = "sweep " + study.string() + " -q --resume -o " + output.string();

    start_journal(study, output);
    write_text(dir / "base.yaml", read_text(dir / "base.yaml") + "# g unchanged, text changed\n");
    auto r = run_mbd(resume);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("'" + (dir / "base.yaml").string() + "' has changed"), std::string::npos) << r.err;

    start_journal(study, output);  // the journal of the changed base: now the scene changes
    write_text(scene, "base: base.yaml\nname: derived-again\n");
    r = run_mbd(resume);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("'" + scene.string() + "' has changed"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(output));

    start_journal(study, output);  // unchanged inputs: every case runs and the file is complete
    r = run_mbd(resume);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(mbd::read_sweep_rows(output).size(), 4u);
    EXPECT_FALSE(fs::exists(output.string() + ".partial"));
}

// ---- memory bounded whatever the case count

// The peak resident memory (kB) of a sweep of `study`: run to its end, or stopped by SIGINT once
// its journal holds a case when `interrupt`.
long sweep_peak_kb(const fs::path& study, const fs::path& output, bool interrupt) {
    // the sanitizer's quarantine kept small in mbd too (see __asan_default_options above)
    const pid_t child = spawn_quiet(mbd::test::mbd_command(
        MBD_EXECUTABLE, "sweep " + study.string() + " -q --flush-seconds 0.01 -o " + output.string()));
    if (interrupt) {
        const fs::path journal = output.string() + ".partial";
        EXPECT_TRUE(wait_until([&] { return fs::exists(journal) && !mbd::read_sweep_rows(output).empty(); }, child))
            << "the sweep recorded no case";
        kill(child, SIGINT);
    }
    return mbd::test::wait_peak_kb(child, interrupt ? 130 : 0, study.string());
}

// A study of 1e8 planned cases (the most a study accepts) starts and runs in the memory of one
// of 100: no table of its cases is made (before, 1e7 cases took 1.4 GB and 1e8 ended in
// bad_alloc). What remains per case is two bits (done or not, in the results and the dispenser).
TEST(SweepMemory, PlannedCasesTakeNoMemory) {
    const fs::path dir = scratch("memory-planned");
    const long small = sweep_peak_kb(write_text(dir / "small.yaml", pendulum_study(pendulum_scene(), 100)), dir / "s.h5", false);
    for (const std::string design : {"monte_carlo", "latin_hypercube"}) {
        const fs::path study = write_text(dir / (design + ".yaml"), pendulum_study(pendulum_scene(), 100000000, 0.1, design));
        const long large = sweep_peak_kb(study, dir / (design + ".h5"), true);
        RecordProperty(design + "_peak_kb", static_cast<int>(large));
        RecordProperty("small_peak_kb", static_cast<int>(small));
        SCOPED_TRACE(design + ": peak " + std::to_string(large) + " kB, against " + std::to_string(small) +
                     " kB for 100 cases");
        EXPECT_LT(large, 200 * 1024);
        EXPECT_LT(large - small, 40 * 1024) << "2 bits per case are 25 MB at 1e8 cases";
    }
}

// A 100,000-case sweep run to its end (issue 41's acceptance): the finished cases stream to the
// journal and from it to the HDF5 file in blocks, so the mbd process's peak memory (its
// ru_maxrss, measured by wait4) stays far under 200 MB and close to that of a 1,000-case
// sweep. Each case is one rk4 step of the pendulum (about 0.1 ms): the count, not the work.
// The sanitizer build runs 20,000 cases (two full blocks of 8,192 and a partial one, as the file
// is written and read, so every path of the streaming): its leak checker finds what a case leaves
// behind, and the growth bound, measured there on memory that includes ASan's shadow, is the
// Release build's check at the full count (docs/ci.md).
TEST(SweepMemory, AHundredThousandCasesRunToTheEndInBoundedMemory) {
    const long count = mbd::test::kSanitizerBuild ? 20000 : 100000;
    const fs::path dir = scratch("memory-100000");
    auto study_of = [&](long cases) {
        std::ostringstream s;
        s << "scene: " << pendulum_scene() << "\n"
          << "analysis: {type: simulate, t_end: 0.01, integrator: rk4, step: 0.01}\n"
          << "parameters:\n  - {path: bodies.bob.mass, distribution: uniform, range: [0.5, 2.0]}\n"
          << "design: {type: monte_carlo, cases: " << cases << ", seed: 3}\nmetrics:\n  - final: bob.x\n";
        return write_text(dir / ("study-" + std::to_string(cases) + ".yaml"), s.str());
    };
    const long small = sweep_peak_kb(study_of(1000), dir / "small.h5", false);
    const fs::path output = dir / "large.h5";
    const fs::path study_file = study_of(count);
    const long large = sweep_peak_kb(study_file, output, false);
    RecordProperty("peak_kb_1000", static_cast<int>(small));
    RecordProperty("peak_kb_" + std::to_string(count), static_cast<int>(large));
    std::printf("sweep peak memory: %ld kB for 1,000 cases, %ld kB for %ld\n", small, large, count);
    EXPECT_LT(large, 200 * 1024);
    EXPECT_LT(large - small, 20 * 1024) << "the table of " << count << " cases would be in memory";

    // every case is in the file, each with its own parameter values
    EXPECT_EQ(mbd::results_h5_shape(output).cases, count);
    const mbd::Study study = mbd::read_study(study_file, mbd::test::shared_registry());
    const mbd::CaseDesign design(study);
    for (long first : {0L, count / 2 - 1, count - 3})
        for (const auto& [k, row] : mbd::read_results_h5(output, first, 3, false)) {
            EXPECT_EQ(row.values, design.values(k));
            EXPECT_TRUE(row.result.ok) << "case " << k << ": " << row.result.message;
        }
}

// The peak resident memory of this process since the last reset_peak() (kB).
long peak_kb() {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line))
        if (line.rfind("VmHWM:", 0) == 0) return std::stol(line.substr(6));
    return -1;
}
void reset_peak() { std::ofstream("/proc/self/clear_refs") << "5"; }

// `n` finished cases, a third of them failed with a 200-character message, through the results:
// the journal, the HDF5 file written from it and the CSV table read back from that. Returns
// how much the peak memory grew (kB); checks that the file holds every case with its values.
long streamed_growth_kb(const fs::path& dir, long n) {
    const fs::path study_file = write_text(dir / "study.yaml", pendulum_study(pendulum_scene(), n));
    const mbd::Study study = mbd::read_study(study_file, mbd::test::shared_registry());
    const mbd::CaseDesign design(study);
    const fs::path output = dir / "r.h5";
    malloc_trim(0);  // what earlier tests freed is no memory this one can reuse unseen
    reset_peak();
    const long before = peak_kb();
    {
        mbd::SweepResults results = mbd::SweepResults::create(output, study, design, {});
        mbd::CaseResult failed;
        failed.failure = "scene";
        failed.message = std::string(200, 'm');
        mbd::CaseResult ok;
        ok.ok = true;
        for (long k = 0; k < n; ++k) {
            ok.metrics = {static_cast<double>(k)};
            results.add(k, k % 3 == 0 ? failed : ok);
            results.flush();
        }
        results.commit();
        results.write_csv(dir / "r.csv");
        EXPECT_EQ(results.failed(), (n + 2) / 3);
    }
    const long growth = peak_kb() - before;

    EXPECT_FALSE(fs::exists(output.string() + ".partial"));
    for (long first : {0L, n / 2, n - 3}) {
        const auto rows = mbd::read_results_h5(output, first, 3, false);
        EXPECT_EQ(rows.size(), 3u);
        for (const auto& [k, row] : rows) {
            EXPECT_EQ(row.values, design.values(k));
            EXPECT_EQ(row.result.ok, k % 3 != 0);
            if (row.result.ok) EXPECT_EQ(row.result.metrics, std::vector<double>{static_cast<double>(k)});
            else EXPECT_EQ(row.result.message.size(), 200u);
        }
    }
    std::ifstream csv(dir / "r.csv");
    long lines = 0;
    for (std::string line; std::getline(csv, line);) ++lines;
    EXPECT_EQ(lines, n + 1);
    return growth;
}

// 50,000 and 200,000 results (10 and 40 MB of records): the peak memory does not grow with
// their number (held in memory, as before, each case took some 250 bytes and the file image
// twice its size: 37 MB more for the larger), and stays far below the records' size.
TEST(SweepMemory, ResultsAreStreamedToTheFile) {
    streamed_growth_kb(scratch("memory-results-warm-up"), 2000);  // the libraries' first allocations
    const long small = streamed_growth_kb(scratch("memory-results-small"), 50000);
    const long large = streamed_growth_kb(scratch("memory-results-large"), 200000);
    RecordProperty("growth_50000_kb", static_cast<int>(small));
    RecordProperty("growth_200000_kb", static_cast<int>(large));
    EXPECT_LT(large, 24 * 1024) << "peak grew by " << large << " kB for 40 MB of records";
    EXPECT_LT(large - small, 4 * 1024) << "50,000 results: " << small << " kB, 200,000: " << large << " kB";
}

// ---- analysis options checked before any case

struct BadAnalysis {
    std::string analysis;  // the analysis line of the study
    std::string key;       // the key the error names
    std::string words;     // in the message
};

TEST(SweepOutputs, AnalysisOptionsThatWouldFailEveryCaseAreRefusedFirst) {
    const fs::path dir = scratch("bad-analysis");
    const std::vector<BadAnalysis> cases{
        {"{type: simulate, t_end: 1,\n  integrator: rk5}", "integrator", "unknown integrator 'rk5'"},
        {"{type: simulate, t_end: 1,\n  formulation: hamiltonain}", "formulation", "hamiltonain"},
        {"{type: simulate, t_end: 1,\n  integrator: rk4}", "type", "rk4 takes fixed steps"},
        {"{type: simulate, t_end: 1, integrator: dopri5,\n  step: 0.001}", "step", "applies to the fixed-step"},
        {"{type: inverse, t_end: 1,\n  step: 0.01}", "type", "needs actuators"},
    };
    for (const BadAnalysis& c : cases) {
        SCOPED_TRACE(c.analysis);
        const fs::path study = write_text(dir / "study.yaml", "scene: " + pendulum_scene() + "\nanalysis: " + c.analysis +
                                                             "\nparameters:\n  - {path: bodies.bob.mass, values: [1, 2]}\n"
                                                             "design: {type: grid}\nmetrics:\n  - final: t\n");
        const auto r = run_mbd("sweep " + study.string() + " -q -o " + (dir / "r.h5").string());
        EXPECT_EQ(r.exit_code, 2) << r.err;
        // the analysis's second line holds the key named; `type` is on its first
        const std::string line = c.key == "type" ? ":2:" : ":3:";
        EXPECT_NE(r.err.find(study.string() + line), std::string::npos) << r.err;
        EXPECT_NE(r.err.find(c.words), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(dir / "r.h5.partial")) << "no case ran: no journal was made";
    }
}

}  // namespace
