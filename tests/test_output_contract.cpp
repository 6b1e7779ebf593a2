// The output contract of every command that writes a file (docs/user-guide.md, "Output
// files and exit status"): an output path that is an input (the scene, a `base:` file,
// by another path or a link) is refused before anything runs; the final name appears
// only for a complete result; a failed, stopped (SIGINT, SIGTERM, SIGHUP) or
// disk-full run leaves its complete rows in NAME.partial, says so, and exits 1, 128 +
// the signal, or 2.
#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>
#include <vector>

#include "support/test_support.hpp"

namespace {

namespace fs = std::filesystem;
using mbd::test::read_csv;
using mbd::test::run_command;
using mbd::test::run_mbd;
using mbd::test::scratch;

std::string scene(const std::string& relative) { return mbd::test::scene_path(relative).string(); }

using mbd::test::read_text;

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// A CSV left by a stopped or failed run: the header's number of finite numbers on every
// row, and the file ends at a row's end. Returns the rows.
std::vector<std::vector<double>> complete_rows(const fs::path& path) {
    const std::string text = read_text(path);
    EXPECT_FALSE(text.empty()) << path;
    if (!text.empty()) EXPECT_EQ(text.back(), '\n') << path << " ends inside a row";
    return read_csv(path).rows;  // every cell a finite number, every row the header's length
}

// A scene folder: a pendulum split into a base file and a scene that inherits it.
struct InheritedScene {
    fs::path dir, base, derived;
    explicit InheritedScene(const std::string& name) : dir(scratch(name)) {
        base = dir / "base.yaml";
        derived = dir / "derived.yaml";
        fs::copy_file(scene("dynamics/pendulum-a01.yaml"), base);
        std::ofstream(derived) << "base: base.yaml\nname: derived\n";
    }
};

// Every command that writes a file refuses an output that is one of its inputs: the
// scene itself, by `./`, by `..`, through a symbolic link, or a base file.
TEST(OutputContract, AnOutputThatIsAnInputIsRefusedBeforeAnythingRuns) {
    const InheritedScene s("inputs");
    fs::create_symlink(s.derived, s.dir / "link.yaml");
    fs::create_directories(s.dir / "sub");
    const std::string derived_text = read_text(s.derived), base_text = read_text(s.base);
    const std::vector<std::string> outputs{s.derived.string(),
                                           (s.dir / "." / "derived.yaml").string(),
                                           (s.dir / "sub" / ".." / "derived.yaml").string(),
                                           (s.dir / "link.yaml").string(),
                                           s.base.string()};
    const std::vector<std::string> commands{
        "simulate " + s.derived.string() + " --t-end 0.1 -q -o ",
        "kinematics " + s.derived.string() + " --t-end 0.1 --step 0.01 -o ",
        "statics " + s.derived.string() + " -o ",
        "bench " + s.derived.string() + " --json " + (s.dir / "b.json").string() + " --csv ",
        "stability " + s.derived.string() + " --markdown ",
    };
    for (const std::string& command : commands)
        for (const std::string& output : outputs) {
            const auto r = run_mbd(command + output);
            EXPECT_EQ(r.exit_code, 2) << command << output << "\n" << r.err;
            EXPECT_TRUE(contains(r.err, "mbd: error:")) << r.err;
            EXPECT_TRUE(contains(r.err, "is the input file")) << command << output << "\n" << r.err;
            EXPECT_EQ(read_text(s.derived), derived_text) << command << output;
            EXPECT_EQ(read_text(s.base), base_text) << command << output;
            EXPECT_FALSE(fs::exists(output + ".partial")) << command << output;
        }
    EXPECT_TRUE(fs::is_symlink(s.dir / "link.yaml"));
}

TEST(OutputContract, AnOutputInAMissingFolderIsRefusedByName) {
    const fs::path dir = scratch("missing-folder");
    const fs::path out = dir / "no-such-folder" / "out.csv";
    const auto r = run_mbd("kinematics " + scene("book/slider-crank.yaml") + " --t-end 0.01 --step 0.001 -o " +
                           out.string());
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_TRUE(contains(r.err, out.string())) << r.err;
    EXPECT_TRUE(contains(r.err, "does not exist")) << r.err;
    EXPECT_TRUE(fs::is_empty(dir));
}

// rk4 with h = 1e-3 on a spring of w = 1e4 rad/s (w h = 10) is unstable: the run stops
// within a few steps. The rows before stay in NAME.partial, an earlier result under
// the final name is left as it was, and the message says where the rows are.
TEST(OutputContract, AFailedRunLeavesItsRowsInThePartialFileAndExitsOne) {
    const fs::path dir = scratch("failed");
    const fs::path out = dir / "stiff.csv";
    std::ofstream(out) << "an earlier complete result\n";
    const auto r = run_mbd("simulate " + scene("dynamics/stiff-spring.yaml") +
                           " --integrator rk4 --step 1e-3 --t-end 1 --output-step 1e-3 --diagnostics -q -o " +
                           out.string());
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_TRUE(contains(r.err, "mbd: error: at t = ")) << r.err;
    EXPECT_TRUE(contains(r.err, out.string() + ".partial' holds the ")) << r.err;
    EXPECT_TRUE(contains(r.err, "'" + out.string() + "' was not written")) << r.err;
    EXPECT_EQ(read_text(out), "an earlier complete result\n");
    const auto rows = complete_rows(out.string() + ".partial");
    ASSERT_GE(rows.size(), 1u);
    EXPECT_EQ(rows.front()[0], 0.0);
    EXPECT_LT(rows.back()[0], 1.0);
}

// A file-size limit (1024 blocks: 512 KiB or 1 MiB, by shell) makes every write beyond
// it fail (EFBIG) like a full disk: exit 2, the path and the cause named, no final name,
// whole rows only in NAME.partial (the blocks written before the failing one).
TEST(OutputContract, AFailedWriteExitsTwoNamingThePath) {
    const fs::path dir = scratch("full");
    const fs::path out = dir / "out.csv";
    const auto r = run_command("trap '' XFSZ; ulimit -f 1024; env -u MBD_PLUGIN_PATH " + std::string(MBD_EXECUTABLE) +
                               " simulate " + scene("dynamics/pendulum-a01.yaml") +
                               " --t-end 100 --output-step 0.001 --tol 1e-8 -q -o " + out.string());
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_TRUE(contains(r.err, "cannot write '" + out.string())) << r.err;
    EXPECT_TRUE(contains(r.err, "File too large")) << r.err;
    EXPECT_FALSE(fs::exists(out));
    const auto rows = complete_rows(out.string() + ".partial");
    EXPECT_GE(rows.size(), 100u);
    EXPECT_LE(fs::file_size(out.string() + ".partial"), 1024u * 1024u);
}

// ---- signals

struct Running {
    pid_t pid = -1;
    fs::path err;
};

// Start mbd with its output on files (the signal goes to mbd itself, not to a shell).
Running start_mbd(const std::vector<std::string>& args, const fs::path& dir) {
    Running run;
    run.err = dir / "stderr.txt";
    const fs::path out = dir / "stdout.txt";
    run.pid = fork();
    if (run.pid == 0) {
        const int o = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        const int e = ::open(run.err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        ::dup2(o, 1);
        ::dup2(e, 2);
        ::unsetenv("MBD_PLUGIN_PATH");
        std::vector<char*> argv{const_cast<char*>(MBD_EXECUTABLE)};
        for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        ::execv(MBD_EXECUTABLE, argv.data());
        ::_exit(127);
    }
    return run;
}

long line_count(const fs::path& p) {
    std::ifstream in(p);
    long n = 0;
    std::string line;
    while (std::getline(in, line)) ++n;
    return n;
}

// Polls (no fixed sleep decides the outcome): true once `done` holds, false at the timeout.
template <class Condition>
bool wait_for(Condition done, std::chrono::seconds timeout) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < end) {
        if (done()) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return done();
}

void expect_stopped_cleanly_by(int signal, int expected_status, const std::string& name) {
    const fs::path dir = scratch("signal-" + name);
    const fs::path out = dir / "out.csv", partial = dir / "out.csv.partial";
    // a run of minutes (dopri5 at tol 1e-10 over 20000 s of the pendulum), stopped early
    const Running run = start_mbd({"simulate", scene("dynamics/pendulum-a01.yaml"), "--t-end", "20000",
                                   "--output-step", "0.01", "--tol", "1e-10", "--diagnostics", "-o", out.string()},
                                  dir);
    ASSERT_GT(run.pid, 0);
    const bool rows_arrived = wait_for([&] { return line_count(partial) >= 20; }, std::chrono::seconds(120));
    int status = 0;
    if (!rows_arrived) {
        ::kill(run.pid, SIGKILL);
        ::waitpid(run.pid, &status, 0);
        FAIL() << "no rows in " << partial << " after 120 s: " << read_text(run.err);
    }
    ASSERT_EQ(::kill(run.pid, signal), 0);
    const bool ended = wait_for([&] { return ::waitpid(run.pid, &status, WNOHANG) == run.pid; }, std::chrono::seconds(60));
    if (!ended) {
        ::kill(run.pid, SIGKILL);
        ::waitpid(run.pid, &status, 0);
        FAIL() << "mbd did not stop within 60 s of " << name;
    }
    const std::string err = read_text(run.err);
    ASSERT_TRUE(WIFEXITED(status)) << "ended by signal " << (WIFSIGNALED(status) ? WTERMSIG(status) : 0) << ": " << err;
    EXPECT_EQ(WEXITSTATUS(status), expected_status) << err;
    EXPECT_TRUE(contains(err, "mbd: error: stopped by " + name + " at t = ")) << err;
    EXPECT_TRUE(contains(err, partial.string() + "' holds the ")) << err;
    EXPECT_FALSE(fs::exists(out)) << "a final-name file after " << name;
    const auto rows = complete_rows(partial);
    ASSERT_GE(rows.size(), 19u);
    // the rows are the run's: consecutive output times 0.01 apart, energy conserved (T + V = 0)
    for (size_t k = 0; k < rows.size(); ++k) {
        EXPECT_NEAR(rows[k][0], 0.01 * static_cast<double>(k), 1e-9) << "row " << k;
        EXPECT_NEAR(rows[k][7] + rows[k][8], 0.0, 1e-6) << "row " << k;
    }
}

TEST(OutputContract, SigintStopsTheRunWithCompleteRowsAndStatus130) { expect_stopped_cleanly_by(SIGINT, 130, "SIGINT"); }

TEST(OutputContract, SigtermStopsTheRunWithCompleteRowsAndStatus143) {
    expect_stopped_cleanly_by(SIGTERM, 143, "SIGTERM");
}

TEST(OutputContract, SighupStopsTheRunWithCompleteRowsAndStatus129) { expect_stopped_cleanly_by(SIGHUP, 129, "SIGHUP"); }

TEST(OutputContract, KinematicsStopsOnSigintToo) {
    const fs::path dir = scratch("signal-kinematics");
    const fs::path out = dir / "k.csv", partial = dir / "k.csv.partial";
    const Running run = start_mbd({"kinematics", scene("book/slider-crank.yaml"), "--t-end", "10000", "--step", "0.002",
                                   "-o", out.string()},
                                  dir);
    ASSERT_GT(run.pid, 0);
    int status = 0;
    if (!wait_for([&] { return line_count(partial) >= 10; }, std::chrono::seconds(120))) {
        ::kill(run.pid, SIGKILL);
        ::waitpid(run.pid, &status, 0);
        FAIL() << "no rows: " << read_text(run.err);
    }
    ::kill(run.pid, SIGINT);
    ASSERT_TRUE(wait_for([&] { return ::waitpid(run.pid, &status, WNOHANG) == run.pid; }, std::chrono::seconds(60)));
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 130) << read_text(run.err);
    EXPECT_FALSE(fs::exists(out));
    const auto rows = complete_rows(partial);
    EXPECT_GE(rows.size(), 9u);
}

}  // namespace
