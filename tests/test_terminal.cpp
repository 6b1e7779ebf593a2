// What a user sees on a terminal (issue 41): mbd runs on a pseudo-terminal of a set width, and
// the raw bytes it writes are replayed through a small model of the terminal's line (carriage
// return, erase to the end of the line, newline). Asserted: no progress line wider than the
// terminal, no message written onto the bar's line (each message starts on a cleared line and
// the bar is drawn again below it), and the bar's line cleared at the end. Also the bench's
// summary counting the skipped peer runs, and the bench finding its peers beside the executable.
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <mbd/progress_bar.hpp>
#include <signal.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iostream>
#include <thread>
#include <fstream>
#include <map>
#include <regex>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using mbd::test::read_text;
using mbd::test::scratch;

struct TerminalRun {
    int exit_code = -1;
    std::string raw;  // every byte the program wrote to the terminal
};

// Runs `child` in a forked process whose stdout and stderr are a new pseudo-terminal of
// `columns` columns (0: the size unknown, as on a serial line), killed after `timeout` seconds;
// `child` ends the process with its exit status. Output post-processing is off (no "\n" ->
// "\r\n"), so the bytes are the program's own.
TerminalRun run_on_terminal(const std::function<int()>& child, int columns, double timeout = 120.0) {
    TerminalRun run;
    struct winsize size {};
    size.ws_row = 24;
    size.ws_col = static_cast<unsigned short>(columns);
    struct termios mode {};
    cfmakeraw(&mode);
    int master = -1, slave = -1;
    if (::openpty(&master, &slave, nullptr, &mode, &size) != 0) {
        ADD_FAILURE() << "openpty failed";
        return run;
    }
    const pid_t pid = ::fork();
    if (pid == 0) {
        ::setsid();
        ::ioctl(slave, TIOCSCTTY, 0);
        const int null = ::open("/dev/null", O_RDONLY);
        ::dup2(null, 0);
        ::dup2(slave, 1);
        ::dup2(slave, 2);
        ::close(master);
        ::_exit(child());
    }
    ::close(slave);
    const auto start = std::chrono::steady_clock::now();
    for (;;) {
        pollfd p{master, POLLIN, 0};
        if (::poll(&p, 1, 200) > 0) {
            char buffer[4096];
            const ssize_t n = ::read(master, buffer, sizeof buffer);
            if (n <= 0) break;  // EIO: every writer of the terminal has gone
            run.raw.append(buffer, static_cast<size_t>(n));
        }
        if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > timeout) {
            ::kill(pid, SIGKILL);
            ADD_FAILURE() << "timed out";
            break;
        }
    }
    ::close(master);
    int status = 0;
    ::waitpid(pid, &status, 0);
    run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return run;
}

// The same for a shell command.
TerminalRun run_on_terminal(const std::string& command, int columns, double timeout = 120.0) {
    return run_on_terminal(
        [&command] {
            ::execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
            return 127;
        },
        columns, timeout);
}

// Columns of a UTF-8 text (a character is one column).
int columns_of(const std::string& text) {
    int n = 0;
    for (char c : text) n += (static_cast<unsigned char>(c) & 0xC0) != 0x80;
    return n;
}

bool is_bar(const std::string& text) { return text.rfind("[", 0) == 0 && text.find(" elapsed, ") != std::string::npos; }

// The raw output replayed on one terminal line: what each redraw of the bar showed, which
// lines ended with a newline (the messages and summaries, in order), and what the line holds
// at the end.
struct Replay {
    std::vector<std::string> bars;      // every bar as drawn
    std::vector<std::string> lines;     // every line as it stood at its newline
    std::vector<bool> after_bar;        // whether a bar had been drawn on that line before it was cleared for it
    std::string last;                   // the line at the end of the output
    std::vector<std::string> unknown;   // escape sequences other than ESC [ K
};

Replay replay(const std::string& raw) {
    Replay r;
    std::string line;
    size_t cursor = 0;
    bool bar_drawn = false;  // since the last newline
    auto end_of_draw = [&] {
        if (is_bar(line)) r.bars.push_back(line), bar_drawn = true;
    };
    for (size_t k = 0; k < raw.size(); ++k) {
        const char c = raw[k];
        if (c == '\r') {
            end_of_draw();
            cursor = 0;
        } else if (c == '\n') {
            end_of_draw();
            r.lines.push_back(line);
            r.after_bar.push_back(bar_drawn);
            line.clear();
            cursor = 0;
            bar_drawn = false;
        } else if (c == '\033') {
            if (raw.compare(k, 3, "\033[K") == 0) {
                line.resize(std::min(line.size(), cursor));
                k += 2;
            } else {
                r.unknown.push_back(raw.substr(k, 4));
            }
        } else {
            if (cursor < line.size()) line[cursor] = c;
            else line += c;
            ++cursor;
        }
    }
    end_of_draw();
    r.last = line;
    return r;
}

// The common promises of a run on a terminal `columns` wide.
void expect_clean_terminal(const Replay& r, int columns, const std::string& what) {
    EXPECT_TRUE(r.unknown.empty()) << what << ": an escape sequence other than ESC [ K";
    ASSERT_FALSE(r.bars.empty()) << what << ": no progress bar drawn (the run must last over a second)";
    // nothing reaches the last column (a full line wraps on some terminals)
    for (const std::string& bar : r.bars) EXPECT_LT(columns_of(bar), columns) << what << ": " << bar;
    for (const std::string& line : r.lines) EXPECT_FALSE(is_bar(line) || line.find(" elapsed, ") != std::string::npos)
        << what << ": a message on the bar's line: " << line;
    EXPECT_EQ(r.last, "") << what << ": the bar's line is not cleared at the end";
    // the percentage never goes back (a redraw after a message shows the bar as it was)
    int before = 0;
    for (const std::string& bar : r.bars) {
        const int percent = std::stoi(bar.substr(bar.find(']') + 1));
        EXPECT_GE(percent, before) << what << ": " << bar;
        EXPECT_LE(percent, 100) << what << ": " << bar;
        before = percent;
    }
}

std::string mbd_command(const std::string& arguments) { return "'" + std::string(MBD_EXECUTABLE) + "' " + arguments; }

// The wall time of a shell command, its output captured.
double wall_seconds(const std::string& command) {
    const auto start = std::chrono::steady_clock::now();
    const mbd::test::CommandResult r = mbd::test::run_command(command);
    EXPECT_EQ(r.exit_code, 0) << command << "\n" << r.err;
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// A simulated duration (a multiple of 0.5 s) that makes `command(t_end)` last about `seconds` of
// wall time on this machine, so the bar (shown after a second) is seen on a fast machine and a
// slow one alike: timed at `base`, scaled (the cost grows with t_end), from `base` to 40 `base`.
double t_end_lasting(double seconds, double base, const std::function<std::string(double)>& command) {
    const double wall = wall_seconds(command(base));
    return std::ceil(2.0 * std::clamp(base * seconds / std::max(wall, 0.05), base, 40.0 * base)) / 2.0;
}

// A bench scene: the A01 pendulum with its closed form run to t_end, an rk4 series of seven
// steps, and peers that are not installed (their three runs are skipped).
fs::path bench_scene(const fs::path& dir, double t_end) {
    std::ifstream src(mbd::test::scene_path("dynamics/pendulum-a01.yaml"));
    const fs::path scene = dir / "pendulum.yaml";
    std::ofstream out(scene);
    std::string line;
    while (std::getline(src, line) && line.rfind("bench:", 0) != 0) out << line << '\n';
    out << "bench:\n  t_end: " << t_end << "\n  output_step: 0.5\n  measure: {body: bob, quantity: position, norm: max}\n"
           "  reference: {kind: closed_form, name: pendulum_a01}\n"
           "  runs:\n    - {formulation: embedding, integrator: rk4, steps: {from: 1.0e-3, to: 1.0e-4, ratio: 1.5}}\n"
           "  peers:\n    model: pendulum_a01\n    simbody: {tolerances: [1.0e-6, 1.0e-7]}\n"
           "    mujoco: {integrator: rk4, steps: [1.0e-3]}\n";
    return scene;
}

// The bench of bench_scene (missing peers, outputs in `dir`); `quiet`: -q.
std::string bench_command(const fs::path& dir, const fs::path& scene, bool quiet = false) {
    return mbd_command("bench '" + scene.string() + "' --repeat 1 --peers '" + (dir / "no-peers").string() +
                       "' --csv '" + (dir / "b.csv").string() + "' --json '" + (dir / "b.json").string() + "'" +
                       (quiet ? " -q" : ""));
}

// A bench_scene t_end for a bench of about three seconds.
double lasting_bench(const fs::path& dir) {
    return t_end_lasting(3.0, 5.0, [&dir](double t_end) { return bench_command(dir, bench_scene(dir, t_end), true); });
}

// Runs command(t_end) on a terminal of `columns`, t_end as timed by t_end_lasting: a run that
// draws fewer than three bars (timed while the machine was busier than during the run) is run
// again three times longer, up to three times; t_end is then the returned run's.
TerminalRun run_lasting(const std::function<std::string(double)>& command, double& t_end, int columns) {
    TerminalRun run = run_on_terminal(command(t_end), columns);
    for (int longer = 0; longer < 3 && run.exit_code == 0 && replay(run.raw).bars.size() < 3; ++longer) {
        t_end *= 3.0;
        run = run_on_terminal(command(t_end), columns);
    }
    return run;
}

// mbd bench on an 80-column terminal: the notes of the missing peers go above the bar (the
// bar is drawn again below each), no line is wider than the terminal, and the summary counts
// the three skipped peer runs and says why.
TEST(Terminal, BenchPrintsItsNotesAboveTheBarWithinTheWidth) {
    const fs::path dir = scratch("terminal-bench");
    double t_end = lasting_bench(dir);
    const TerminalRun run =
        run_lasting([&](double t) { return bench_command(dir, bench_scene(dir, t)); }, t_end, 80);
    ASSERT_EQ(run.exit_code, 0) << run.raw;
    const Replay r = replay(run.raw);
    expect_clean_terminal(r, 80, "bench");
    // the two notes, each printed on a line the bar had been drawn on and then cleared
    int notes_over_bar = 0;
    for (size_t k = 0; k < r.lines.size(); ++k)
        if (r.lines[k].find(": not installed (") != std::string::npos) {
            EXPECT_EQ(r.lines[k].rfind("mbd bench: ", 0), 0u) << r.lines[k];  // from the line's start
            notes_over_bar += r.after_bar[k];
        }
    EXPECT_GE(notes_over_bar, 1) << "no note came while the bar was shown: the test does not test what it says";
    // the summary: the seven rk4 steps 1e-3 ... 1e-4 (ratio 10^(1/6)) ran, the 2 + 1 peer points were skipped
    const std::string summary = "pendulum-a01: 10 runs (7 ok, 0 failed, 0 skipped after a failure of their series); "
                                "3 peer runs skipped (not installed: simbody, mujoco)";
    bool found = false;
    for (const std::string& line : r.lines) found = found || line.rfind(summary, 0) == 0;
    EXPECT_TRUE(found) << run.raw.substr(run.raw.size() > 2000 ? run.raw.size() - 2000 : 0);
    EXPECT_EQ(r.lines.back().rfind("wrote ", 0), 0u) << r.lines.back();
}

// mbd sweep on an 80-column terminal: the bar counts the cases, stays within the width, and
// its line is cleared before the summary.
TEST(Terminal, SweepBarStaysWithinTheWidthAndIsClearedAtTheEnd) {
    const fs::path dir = scratch("terminal-sweep");
    const fs::path study = dir / "study.yaml";
    auto sweep = [&](double t_end) {
        std::ofstream(study) << "scene: " << mbd::test::scene_path("dynamics/pendulum-a01.yaml").string()
                             << "\nanalysis: {type: simulate, t_end: " << t_end
                             << ", integrator: rk4, step: 1.0e-4}\nparameters:\n"
                                "  - {path: bodies.bob.mass, values: [0.5, 0.75, 1, 1.25, 1.5, 1.75, 2, 2.5]}\n"
                                "design: {type: grid}\nmetrics: [{final: bob.y}]\n";
        fs::remove(dir / "r.h5");
        return mbd_command("sweep '" + study.string() + "' -o '" + (dir / "r.h5").string() + "'");
    };
    double t_end = t_end_lasting(3.0, 1.0, [&](double t) { return sweep(t) + " -q"; });
    const TerminalRun run = run_lasting(sweep, t_end, 80);
    ASSERT_EQ(run.exit_code, 0) << run.raw;
    const Replay r = replay(run.raw);
    expect_clean_terminal(r, 80, "sweep");
    EXPECT_NE(r.bars.back().find(" / 8 cases"), std::string::npos) << r.bars.back();
}

// On a terminal whose size is unknown (0 columns), $COLUMNS sets the width.
TEST(Terminal, ColumnsSetsTheWidthWhenTheTerminalDoesNotSay) {
    const fs::path dir = scratch("terminal-columns");
    double t_end = lasting_bench(dir);
    const TerminalRun run =
        run_lasting([&](double t) { return "COLUMNS=50 " + bench_command(dir, bench_scene(dir, t)); }, t_end, 0);
    ASSERT_EQ(run.exit_code, 0) << run.raw;
    const Replay r = replay(run.raw);
    ASSERT_FALSE(r.bars.empty());
    for (const std::string& bar : r.bars) EXPECT_EQ(columns_of(bar), 49) << bar;  // cut at the width less one
}

// mbd stability shows the running case and its simulated time on a progress line: the A01
// pendulum case, run for about three seconds, is seen at several times of its run, and its
// matrix line goes above the bar.
TEST(Terminal, StabilityShowsTheRunningCaseAndItsTime) {
    const fs::path dir = scratch("terminal-stability");
    const std::string original = read_text(mbd::test::scene_path("extreme/pendulum-a01-2000s.yaml"));
    const fs::path scene = dir / "pendulum-a01-2000s.yaml";  // the matrix names a case by its file
    auto stability = [&](double t_end) {
        // the terminal is tested, not the accuracy: a run made longer to last keeps its "pass"
        // (the bob's position error stays below 10 m, the wall time below 600 s)
        std::string text = mbd::test::replaced(original, "t_end: 2000.0", "t_end: " + mbd::test::g17(t_end));
        text = mbd::test::replaced(mbd::test::replaced(text, "bound: 1.0e-3", "bound: 10"), "budget: 40", "budget: 600");
        std::ofstream(scene) << text;
        return mbd_command("stability '" + scene.string() + "' --formulation augmented --integrator dopri5");
    };
    double t_end = t_end_lasting(3.0, 100.0, stability);
    const TerminalRun run = run_lasting(stability, t_end, 120);
    ASSERT_EQ(run.exit_code, 0) << run.raw;
    const Replay r = replay(run.raw);
    expect_clean_terminal(r, 120, "stability");
    const std::regex shown(R"(pendulum-a01-2000s augmented dopri5 t = ([0-9.e+]+) / ([0-9.e+]+) s, cell 1/1$)");
    std::vector<double> times;
    for (const std::string& bar : r.bars) {
        std::smatch m;
        if (!std::regex_search(bar, m, shown)) continue;
        times.push_back(std::stod(m[1]));
        EXPECT_NEAR(std::stod(m[2]), t_end, 5e-4 * t_end) << bar;  // four digits of the case's t_end
    }
    ASSERT_GE(times.size(), 2u) << (r.bars.empty() ? std::string() : r.bars.back());
    for (size_t k = 1; k < times.size(); ++k) EXPECT_GE(times[k], times[k - 1]);  // time only goes forward
    EXPECT_GT(times.back(), times.front()) << "the progress line did not move during the case";
    EXPECT_LE(times.back(), t_end);
    ASSERT_GE(r.lines.size(), 2u);
    EXPECT_EQ(r.lines[0].rfind("pendulum-a01-2000s", 0), 0u) << r.lines[0];
    EXPECT_NE(r.lines[0].find("pass"), std::string::npos) << r.lines[0];
}

// The mechanism itself (mbd simulate's formulation messages reach it through std::clog, the
// default MessageLog): while a bar is shown, a line through console_line, a line written to
// std::clog, one written to std::cerr in two pieces, and lines of two threads at once each land
// on a cleared line of their own, the bar drawn again after each; the line is cleared at the end.
TEST(Terminal, MessagesWhileTheBarIsShownGoAboveIt) {
    const TerminalRun run = run_on_terminal(
        [] {
            {
                mbd::ProgressBar bar(true);
                std::this_thread::sleep_for(std::chrono::milliseconds(1100));  // the bar waits a second
                bar.update(0.25, "first");
                mbd::console_line("a note");
                std::clog << "a formulation message\n";
                std::cerr << "two " << "pieces" << std::flush;
                std::cerr << " of one line" << std::endl;
                auto talk = [](const char* who) {
                    for (int k = 0; k < 50; ++k) std::clog << who << " line " << k << '\n';
                };
                std::thread a(talk, "thread a"), b(talk, "thread b");
                a.join();
                b.join();
                std::this_thread::sleep_for(std::chrono::milliseconds(150));
                bar.update(0.5, std::string(200, 'x'));  // a detail far wider than the terminal
                mbd::console_line("done", stdout);
            }
            std::cerr << "after the bar\n";
            return 0;
        },
        60);
    ASSERT_EQ(run.exit_code, 0) << run.raw;
    const Replay r = replay(run.raw);
    expect_clean_terminal(r, 60, "messages");
    ASSERT_EQ(r.bars.size(), 106u);  // two updates, and a redraw after each of the 104 messages
    EXPECT_EQ(columns_of(r.bars.back()), 59);
    ASSERT_EQ(r.lines.size(), 105u);
    EXPECT_EQ(r.lines[0], "a note");
    EXPECT_EQ(r.lines[1], "a formulation message");
    EXPECT_EQ(r.lines[2], "two pieces of one line");
    std::map<std::string, int> seen;
    for (size_t k = 3; k < 103; ++k) ++seen[r.lines[k]];
    for (const char* who : {"thread a", "thread b"})
        for (int k = 0; k < 50; ++k) EXPECT_EQ(seen[std::string(who) + " line " + std::to_string(k)], 1) << who << k;
    EXPECT_EQ(r.lines[103], "done");
    EXPECT_EQ(r.lines[104], "after the bar");  // std::cerr is itself again
    for (size_t k = 0; k < 104; ++k) EXPECT_TRUE(r.after_bar[k]) << k << ": " << r.lines[k];
}

// mbd bench finds the peers built with it without --peers: a copy of mbd in a folder of its
// own finds a peer in bin/peers beside it (the build tree's layout) and one in
// libexec/mbd/peers (the install tree's); each fake peer prints a CPU time and step count of
// its own and the bob at rest at its start, so its row shows it was the one that ran.
TEST(BenchPeers, FoundBesideTheExecutableWithoutThePeersOption) {
    const fs::path dir = scratch("peer-discovery");
    const fs::path bin = dir / "bin";
    fs::create_directories(bin / "peers");
    fs::create_directories(dir / "libexec" / "mbd" / "peers");
    fs::copy_file(MBD_EXECUTABLE, bin / "mbd");
    // the peer protocol (bench.cpp): "cpu_s steps", then "t x y z" per output time
    auto fake_peer = [](const fs::path& path, const std::string& cpu_and_steps) {
        std::ofstream(path) << "#!/bin/sh\necho '" << cpu_and_steps << "'\necho '0.5 1 0 0'\necho '1 1 0 0'\n";
        fs::permissions(path, fs::perms::owner_all);
    };
    fake_peer(bin / "peers" / "mbd_peer_simbody", "0.125 42");
    fake_peer(dir / "libexec" / "mbd" / "peers" / "mbd_peer_mujoco", "0.25 7");
    std::ifstream src(mbd::test::scene_path("dynamics/pendulum-a01.yaml"));
    const fs::path scene = dir / "pendulum.yaml";
    {
        std::ofstream out(scene);
        std::string line;
        while (std::getline(src, line) && line.rfind("bench:", 0) != 0) out << line << '\n';
        out << "bench:\n  t_end: 1\n  output_step: 0.5\n  measure: {body: bob, quantity: position, norm: max}\n"
               "  reference: {kind: closed_form, name: pendulum_a01}\n"
               "  runs:\n    - {formulation: embedding, integrator: dopri5, tolerances: [1.0e-6]}\n"
               "  peers:\n    model: pendulum_a01\n    simbody: {tolerances: [1.0e-6]}\n"
               "    mujoco: {integrator: rk4, steps: [1.0e-3]}\n";
    }
    const fs::path csv = dir / "b.csv";
    const mbd::test::CommandResult r =
        mbd::test::run_command("'" + (bin / "mbd").string() + "' bench '" + scene.string() + "' --repeat 1 --csv '" +
                               csv.string() + "' --json '" + (dir / "b.json").string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.err.find("not installed"), std::string::npos) << r.err;
    EXPECT_NE(r.out.find("pendulum-a01: 3 runs (3 ok, 0 failed, 0 skipped after a failure of their series); reference"),
              std::string::npos)
        << r.out;
    // the bob at rest at (1, 0) against the closed form: the largest distance over t = 0.5, 1
    double worst = 0.0;
    for (double t : {0.5, 1.0}) worst = std::max(worst, (mbd::test::a01_bob_position(t) - Eigen::Vector2d(1, 0)).norm());
    const std::string table = read_text(csv);
    for (const char* row : {R"(\nsimbody,pendulum-a01,simbody,[^,]*,1e-06,,0.125,42,([0-9.e+-]+),[^\n]*,ok\n)",
                            R"(\nmujoco,pendulum-a01,mujoco,rk4,,0.001,0.25,7,([0-9.e+-]+),[^\n]*,ok\n)"}) {
        std::smatch m;
        ASSERT_TRUE(std::regex_search(table, m, std::regex(row))) << row << "\n" << table;
        EXPECT_NEAR(std::stod(m[1]), worst, 1e-6 * worst) << row;
    }
}

}  // namespace
