// Checked input and named causes on the command line (issue 20): every number is
// finite and in range or refused by option name; an integrator option that does not
// apply is an error; a conservative run that gains energy without bound stops with a
// diagnosis; a plugin's exception, a joint turning NaN, an overflowing driver and
// statics without equilibrium are each named; `mbd --help` lists the commands; `-q`
// is quiet; the progress bar redraws its line cleanly.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "support/test_support.hpp"

namespace {

namespace fs = std::filesystem;
using mbd::test::read_csv;
using mbd::test::run_command;
using mbd::test::run_mbd;
using mbd::test::scratch;

std::string scene(const std::string& relative) { return mbd::test::scene_path(relative).string(); }

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// A refused command line: exit 2, the option and the value named, nothing written, and
// no absurd number in the message (a 309-digit range, a NaN time).
void expect_refused(const std::string& arguments, const std::vector<std::string>& named, const fs::path& output) {
    const auto r = run_mbd(arguments);
    EXPECT_EQ(r.exit_code, 2) << arguments << "\n" << r.err;
    EXPECT_TRUE(contains(r.err, "mbd: error:")) << r.err;
    for (const std::string& part : named) EXPECT_TRUE(contains(r.err, part)) << arguments << ": no '" << part << "' in\n" << r.err;
    EXPECT_FALSE(std::regex_search(r.err, std::regex("[0-9]{20}"))) << r.err;
    EXPECT_FALSE(contains(r.err, "t = nan") || contains(r.err, "t = -nan")) << r.err;
    EXPECT_LT(r.err.size(), 600u) << r.err;
    if (!output.empty()) {
        EXPECT_FALSE(fs::exists(output)) << arguments;
        EXPECT_FALSE(fs::exists(output.string() + ".partial")) << arguments;
    }
}

TEST(CliNumbers, SimulateRefusesNumbersThatAreNotFiniteOrOutOfRange) {
    const fs::path out = scratch("numbers") / "out.csv";
    const std::string base = "simulate " + scene("dynamics/pendulum-a01.yaml") + " -o " + out.string() + " ";
    expect_refused(base + "--t-end 1 --tol nan", {"--tol", "nan"}, out);
    expect_refused(base + "--t-end 1 --tol 1e-300", {"--tol", "1e-300", "1e-14"}, out);
    expect_refused(base + "--t-end 1 --tol 2", {"--tol", "2"}, out);
    expect_refused(base + "--t-end 1 --output-step nan", {"--output-step", "nan"}, out);
    expect_refused(base + "--t-end 1 --output-step 0", {"--output-step", "0"}, out);
    expect_refused(base + "--t-end 1 --output-step 1e-300", {"--output-step", "rows"}, out);
    expect_refused(base + "--t-end 1 --integrator rk4 --step 0", {"--step", "positive"}, out);
    expect_refused(base + "--t-end 1 --integrator rk4 --step inf", {"--step", "inf"}, out);
    expect_refused(base + "--t-end 1 --integrator rk4 --step 1e-300", {"--step", "steps"}, out);
    expect_refused(base + "--t-end nan", {"--t-end", "nan"}, out);
    expect_refused(base + "--t-end -1", {"--t-end", "-1"}, out);
    expect_refused(base + "--t-end 0", {"--t-end", "0"}, out);
    expect_refused(base + "--t-end 1e400", {"--t-end", "1e400"}, out);
    expect_refused(base + "--t-end 1x", {"--t-end", "1x"}, out);
}

TEST(CliNumbers, KinematicsInverseStaticsAndCheckRefuseBadNumbers) {
    const fs::path out = scratch("numbers-other") / "out.csv";
    const std::string crank = scene("book/slider-crank.yaml");
    // 1e-300 would write 1e300 rows: refused, not one row and success
    expect_refused("kinematics " + crank + " --t-end 1 --step 1e-300 -o " + out.string(), {"--step", "rows"}, out);
    expect_refused("kinematics " + crank + " --t-end 1 --step 0 -o " + out.string(), {"--step", "0"}, out);
    expect_refused("kinematics " + crank + " --t-end nan --step 0.1 -o " + out.string(), {"--t-end", "nan"}, out);
    expect_refused("kinematics " + crank + " --t-end -1 --step 0.1 -o " + out.string(), {"--t-end", "-1"}, out);
    expect_refused("kinematics " + crank + " --t-end 1 --step 0.1 --tolerance nan", {"--tolerance", "nan"}, {});
    expect_refused("inverse " + crank + " --t-end 1 --step 1e-300 -o " + out.string(), {"--step", "rows"}, out);
    expect_refused("statics " + scene("statics/pendulum-torque.yaml") + " --time nan", {"--time", "nan"}, {});
    expect_refused("statics " + scene("statics/pendulum-torque.yaml") + " --tolerance 0", {"--tolerance", "0"}, {});
    expect_refused("check " + crank + " --rank-tolerance nan", {"--rank-tolerance", "nan"}, {});
    expect_refused("bench " + crank + " --min-tol nan", {"--min-tol", "nan"}, {});
}

TEST(CliNumbers, AnIntegratorOptionThatDoesNotApplyIsNamed) {
    const fs::path out = scratch("integrator-options") / "out.csv";
    const std::string base = "simulate " + scene("dynamics/pendulum-a01.yaml") + " --t-end 1 -o " + out.string() + " ";
    // --step is the fixed step of rk4, euler and generalized_alpha, never dopri5's output step
    expect_refused(base + "--integrator dopri5 --step 0.01", {"--step", "dopri5", "--output-step"}, out);
    expect_refused(base + "--integrator cvode --step 0.01", {"--step", "cvode"}, out);
    expect_refused(base + "--step 0.01", {"--step", "dop853"}, out);  // dop853 is the automatic choice (not stiff)
    expect_refused(base + "--integrator rk4 --tol 1e-8", {"--tol", "rk4", "--step"}, out);
    expect_refused(base + "--integrator generalized_alpha --tol 1e-8", {"--tol", "generalized_alpha"}, out);
    expect_refused(base + "--integrator rk4", {"--step", "rk4"}, out);
    // the options that apply are taken
    const auto ok = run_mbd(base + "--integrator rk4 --step 0.01 -q");
    EXPECT_EQ(ok.exit_code, 0) << ok.err;
    EXPECT_EQ(read_csv(out).rows.size(), 101u);  // --output-step defaults to the fixed step
}

// rk4 at w h = 3.2 on the k = 1e8 spring is just outside its stability interval (2.83):
// the amplitude grows by a few per cent a step, so T + V (50 J, constant in the closed
// form of scenes/dynamics/stiff-spring.yaml) grows geometrically. The run must stop with
// that diagnosis once the gain passes 100 times the motion's energy, long before the
// state itself is out of bounds.
TEST(CliEnergy, AConservativeRunThatGainsEnergyStopsWithADiagnosis) {
    const fs::path dir = scratch("energy");
    const fs::path out = dir / "spring.csv";
    const auto r = run_mbd("simulate " + scene("dynamics/stiff-spring.yaml") +
                           " --integrator rk4 --step 3.2e-4 --t-end 0.05 --diagnostics -q -o " + out.string());
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_TRUE(contains(r.err, "total energy")) << r.err;
    EXPECT_TRUE(contains(r.err, "conservative")) << r.err;
    EXPECT_TRUE(contains(r.err, "smaller step")) << r.err;
    EXPECT_FALSE(fs::exists(out));
    // |R(3.2 i)| = 2.27 for rk4: the energy grows 5.2-fold a step, so the gain passes
    // 100 x 50 J at the third step; the rows before it are kept, each below that bound
    const auto csv = read_csv(out.string() + ".partial");
    ASSERT_GE(csv.rows.size(), 2u);
    EXPECT_LE(csv.rows.size(), 4u);
    const int T = csv.column("kinetic_energy"), V = csv.column("potential_energy");
    const double E0 = csv.rows.front()[T] + csv.rows.front()[V];
    EXPECT_NEAR(E0, 50.0, 1e-6);
    for (const auto& row : csv.rows) EXPECT_LT(row[T] + row[V], E0 + 100.0 * 50.0 * 1.000001);
}

// The case of issue 20: generalized-alpha at h = 0.01 on the same spring (w h = 100)
// gains energy by three orders of magnitude in one step and used to end with status 0.
TEST(CliEnergy, GeneralizedAlphaGainingEnergyOnTheStiffSpringIsStopped) {
    const fs::path out = scratch("energy-ga") / "spring.csv";
    const auto r = run_mbd("simulate " + scene("dynamics/stiff-spring.yaml") +
                           " --integrator generalized_alpha --step 0.01 --t-end 10 -q -o " + out.string());
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_TRUE(contains(r.err, "total energy T + V grew from 50 ")) << r.err;
    EXPECT_TRUE(contains(r.err, "unstable")) << r.err;
    EXPECT_FALSE(fs::exists(out));
}

TEST(CliEnergy, AnAccurateConservativeRunIsNotStopped) {
    // the same spring at a stable step (w h = 1), and the pendulum released from E0 = 0
    const fs::path dir = scratch("energy-ok");
    const auto spring = run_mbd("simulate " + scene("dynamics/stiff-spring.yaml") +
                                " --integrator rk4 --step 1e-4 --t-end 0.05 --diagnostics -q -o " +
                                (dir / "s.csv").string());
    EXPECT_EQ(spring.exit_code, 0) << spring.err;
    // rk4 on x'' = -w^2 x at w h = 1 multiplies the energy by |R(i)|^2 = (13/24)^2 + (5/6)^2
    // = 569/576 a step (it dissipates): E_k = 50 (569/576)^k, never a gain
    const auto csv = read_csv(dir / "s.csv");
    ASSERT_EQ(csv.rows.size(), 501u);
    for (size_t k = 0; k < csv.rows.size(); ++k) {
        const double E = csv.rows[k][csv.column("kinetic_energy")] + csv.rows[k][csv.column("potential_energy")];
        EXPECT_NEAR(E / (50.0 * std::pow(569.0 / 576.0, static_cast<double>(k))), 1.0, 1e-6) << "row " << k;
    }
    const auto pendulum = run_mbd("simulate " + scene("dynamics/pendulum-a01.yaml") +
                                  " --integrator rk4 --step 1e-3 --t-end 3 -q -o " + (dir / "p.csv").string());
    EXPECT_EQ(pendulum.exit_code, 0) << pendulum.err;
}

// ---- messages that name the element and the cause

std::string write_scene(const fs::path& dir, const std::string& name, const std::string& text) {
    const fs::path p = dir / name;
    std::ofstream(p) << text;
    return p.string();
}

mbd::test::CommandResult run_with_test_plugins(const std::string& arguments) {
    return run_command(std::string("env MBD_PLUGIN_PATH=") + MBD_TEST_PLUGIN_DIR + " " + MBD_EXECUTABLE + " " + arguments);
}

const char* kPinScene = R"(dimension: planar
gravity: [0, -9.81]
bodies:
  - {name: bob, mass: 1, inertia: 0.01, position: [1, 0]}
joints:
  - name: pin
    type: fragile_pin
    bodies: [ground, bob]
    point: [0, 0]
    breaks_at: %BREAKS%
)";

std::string pin_scene(const fs::path& dir, const std::string& breaks_at) {
    std::string text = kPinScene;
    text.replace(text.find("%BREAKS%"), 8, breaks_at);
    return write_scene(dir, "pin.yaml", text);
}

TEST(CliMessages, APluginFactorysExceptionNamesTheFileTheJointAndThePlugin) {
    const fs::path dir = scratch("factory");
    const std::string file = pin_scene(dir, "-1");
    const auto r = run_with_test_plugins("check " + file);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_TRUE(contains(r.err, file + ":")) << r.err;                 // the scene file and line
    EXPECT_TRUE(contains(r.err, "joint 'pin'")) << r.err;              // the joint
    EXPECT_TRUE(contains(r.err, "breaks_at must be positive")) << r.err;  // the plugin's own words
    EXPECT_TRUE(contains(r.err, "libmbd_joint_fragile_pin")) << r.err;  // the library
}

TEST(CliMessages, AJointTurningNanIsNamedNotCalledAProjectionFailure) {
    const fs::path dir = scratch("nan-joint");
    const std::string file = pin_scene(dir, "0.25");
    const fs::path out = dir / "out.csv";
    const auto r = run_with_test_plugins("simulate " + file + " --t-end 1 --tol 1e-8 -q -o " + out.string());
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_TRUE(contains(r.err, "joint 'pin'")) << r.err;
    EXPECT_TRUE(contains(r.err, "fragile_pin")) << r.err;
    EXPECT_TRUE(contains(r.err, "row 'x'")) << r.err;
    EXPECT_TRUE(contains(r.err, "non-finite")) << r.err;
    EXPECT_FALSE(contains(r.err, "projection")) << r.err;
    EXPECT_FALSE(fs::exists(out));
    // the rows before t = 0.25 are kept, each complete
    const auto csv = read_csv(out.string() + ".partial");
    ASSERT_FALSE(csv.rows.empty());
    EXPECT_LT(csv.rows.back()[0], 0.25);
}

TEST(CliMessages, AnOverflowingDriverIsNamedNotCalledASingularJacobian) {
    const fs::path dir = scratch("overflow");
    const std::string file = write_scene(dir, "spin.yaml", R"(dimension: planar
bodies:
  - {name: crank, mass: 1, inertia: 0.1, position: [0.5, 0]}
joints:
  - {name: pin, type: revolute, bodies: [ground, crank], point: [0, 0]}
drivers:
  - {name: spin, joint: pin, motion: {type: harmonic, amplitude: 1.0e308, frequency: 10}}
)");
    // f = A sin(w t) is finite (0 at t = 0), its rate A w overflows to inf
    const auto r = run_mbd("kinematics " + file + " --t-end 1 --step 0.1");
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_TRUE(contains(r.err, "driver 'spin'")) << r.err;
    EXPECT_TRUE(contains(r.err, file + ":7")) << r.err;
    EXPECT_TRUE(contains(r.err, "not finite")) << r.err;
    EXPECT_TRUE(contains(r.err, "df/dt = inf")) << r.err;
    EXPECT_FALSE(contains(r.err, "singular")) << r.err;
}

TEST(CliMessages, StaticsWithoutEquilibriumBlamesTheLoadsNotTheConstraints) {
    // a bar pinned at its end, no gravity, a constant torque: nothing can balance it
    const fs::path dir = scratch("no-equilibrium");
    const std::string file = write_scene(dir, "torque.yaml", R"(dimension: planar
bodies:
  - {name: bar, mass: 1, inertia: 0.08, position: [0.5, 0]}
joints:
  - {name: pin, type: revolute, bodies: [ground, bar], point: [0, 0]}
forces:
  - {name: motor, type: point_torque, body: bar, torque: 2}
)");
    const auto r = run_mbd("statics " + file + " --objective virtual-work");
    EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
    EXPECT_TRUE(contains(r.err, "no equilibrium")) << r.err;
    EXPECT_FALSE(contains(r.err, "no configuration satisfies the joints")) << r.err;
}

// ---- help, quiet, progress

TEST(CliHelp, TheTopLevelHelpDescribesTheCommandsAndTheExitStatus) {
    const auto help = run_mbd("--help");
    EXPECT_EQ(help.exit_code, 0);
    for (const char* word : {"simulate", "kinematics", "statics", "inverse", "bench", "stability", "check", "plugins",
                             "Exit status", "130", ".partial"})
        EXPECT_TRUE(contains(help.out, word)) << word << "\n" << help.out;
    EXPECT_FALSE(contains(help.out, "(kinematics, mobility, plugins)")) << help.out;
}

TEST(CliQuiet, QuietSilencesTheFormulationsMessages) {
    // the embedding formulation reports its path choice; -q drops it (and everything but errors)
    const fs::path dir = scratch("quiet");
    const std::string run = "simulate " + scene("dynamics/four-bar-spring-damper.yaml") +
                            " --formulation embedding --t-end 0.05 -o " + (dir / "x.csv").string();
    const auto loud = run_mbd(run);
    ASSERT_EQ(loud.exit_code, 0) << loud.err;
    EXPECT_TRUE(contains(loud.err, "embedding:")) << loud.err;
    EXPECT_TRUE(contains(loud.out, "simulated")) << loud.out;
    const auto quiet = run_mbd(run + " -q");
    ASSERT_EQ(quiet.exit_code, 0) << quiet.err;
    EXPECT_EQ(quiet.err, "");
    EXPECT_EQ(quiet.out, "");
    EXPECT_EQ(read_csv(dir / "x.csv").rows.size(), 1001u);
}

TEST(CliProgress, TheBarRedrawsItsWholeLineWithElapsedTimeAndTimeLeft) {
    // on a terminal (script(1) gives a pseudo-terminal), a run of a few seconds
    const fs::path dir = scratch("progress");
    const fs::path log = dir / "terminal.txt";
    const std::string run = " simulate " + scene("dynamics/pendulum-a01.yaml") +
                            " --formulation augmented --tol 1e-10 --output-step 0.1 -o " + (dir / "p.csv").string();
    // the pace of this build and machine (a sanitizer build is some 30 times slower) sizes a
    // run of about 3 s: long enough for the bar, which appears after 1 s. From two runs, so
    // that the start-up (loading the plugins: most of a short run) cancels, bounded below by a
    // quarter of the longer run's average pace (a load spike cannot make the difference vanish)
    const auto seconds_for = [&](double t_end) {
        const auto start = std::chrono::steady_clock::now();
        EXPECT_EQ(run_mbd(run + " --t-end " + std::to_string(t_end)).exit_code, 0);
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };
    const double short_run = seconds_for(200.0), long_run = seconds_for(800.0);
    const double pace = std::max((long_run - short_run) / 600.0, 0.25 * long_run / 800.0);
    const double t_end = std::clamp(3.0 / pace, 50.0, 20000.0);
    const auto r = run_command("script -qec 'env -u MBD_PLUGIN_PATH COLUMNS=100 " + std::string(MBD_EXECUTABLE) + run +
                               " --t-end " + std::to_string(t_end) + "' " + log.string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::ifstream in(log);
    std::stringstream s;
    s << in.rdbuf();
    const std::string text = s.str();
    // every redraw returns to the line's start and clears it before writing
    size_t redraws = 0;
    for (size_t at = text.find('\r'); at != std::string::npos; at = text.find('\r', at + 1)) {
        if (at + 1 < text.size() && text[at + 1] == '\n') continue;  // the terminal's own line end
        EXPECT_EQ(text.compare(at, 4, "\r\033[K"), 0) << "a redraw that does not clear the line at " << at;
        ++redraws;
    }
    EXPECT_GT(redraws, 0u) << "no progress bar in a run of several seconds";
    EXPECT_TRUE(contains(text, "elapsed")) << text.substr(0, 400);
    EXPECT_TRUE(contains(text, "left")) << text.substr(0, 400);
}

}  // namespace
