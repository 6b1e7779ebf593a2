// The mbd command: --help and --version, `mbd plugins`, `mbd check` exit codes,
// `mbd kinematics` CSV output in the column contract of mbd/csv.hpp, and
// errors ("mbd: error: ...", non-zero exit, no partial output file).
#include <mbd/csv.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

#include "support/test_support.hpp"

namespace {

using mbd::test::scratch;

namespace fs = std::filesystem;
using mbd::test::run_mbd;

std::string book_scene(const std::string& name) {
    return (fs::path(MBD_SOURCE_DIR) / "scenes/book" / name).string();
}

using mbd::test::read_text;

std::vector<std::string> split(const std::string& line, char sep) {
    std::vector<std::string> out;
    std::stringstream s(line);
    std::string item;
    while (std::getline(s, item, sep)) out.push_back(item);
    return out;
}

std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out = split(text, '\n');
    while (!out.empty() && out.back().empty()) out.pop_back();
    return out;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(Cli, VersionAndHelpOnEverySubcommand) {
    const auto version = run_mbd("--version");
    EXPECT_EQ(version.exit_code, 0);
    EXPECT_TRUE(contains(version.out, "mbd ")) << version.out;
    for (const char* sub : {"", "plugins ", "check ", "kinematics "}) {
        const auto help = run_mbd(std::string(sub) + "--help");
        EXPECT_EQ(help.exit_code, 0) << sub << help.err;
        EXPECT_TRUE(contains(help.out, "Usage")) << sub << help.out;
    }
    // simulate and statics are commands: each has its help, and without its scene it is a
    // command-line error naming the missing argument
    for (const char* command : {"simulate", "statics"}) {
        const auto help = run_mbd(std::string(command) + " --help");
        EXPECT_EQ(help.exit_code, 0) << command << help.err;
        EXPECT_TRUE(contains(help.out, "Usage")) << command << help.out;
        EXPECT_TRUE(contains(help.out, "SCENE")) << command << help.out;
        const auto r = run_mbd(command);
        EXPECT_EQ(r.exit_code, 2) << command;
        EXPECT_TRUE(contains(r.err, "mbd: error:")) << r.err;
        EXPECT_TRUE(contains(r.err, "SCENE")) << command << ": " << r.err;
    }
    // a command that does not exist
    const auto unknown = run_mbd("simulat");
    EXPECT_EQ(unknown.exit_code, 2);
    EXPECT_TRUE(contains(unknown.err, "mbd: error:")) << unknown.err;
    EXPECT_TRUE(contains(unknown.err, "simulat")) << unknown.err;
}

TEST(Cli, PluginsListsJointsAndForcesWithTheirLibraries) {
    const auto r = run_mbd("plugins");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(contains(r.out, "joint")) << r.out;
    EXPECT_TRUE(contains(r.out, "revolute")) << r.out;
    EXPECT_TRUE(contains(r.out, "spherical")) << r.out;
    EXPECT_TRUE(contains(r.out, "force")) << r.out;
    EXPECT_TRUE(contains(r.out, "gravity")) << r.out;
    EXPECT_TRUE(contains(r.out, "libmbd_joint_revolute")) << r.out;
    EXPECT_TRUE(contains(r.out, "ABI")) << r.out;
}

TEST(Cli, CheckExitCodes) {
    EXPECT_EQ(run_mbd("check " + book_scene("slider-crank.yaml")).exit_code, 0);
    EXPECT_EQ(run_mbd("check " + book_scene("bricard.yaml")).exit_code, 0);
    // no scene argument: command-line error
    const auto missing_argument = run_mbd("check");
    EXPECT_EQ(missing_argument.exit_code, 2);
    EXPECT_TRUE(contains(missing_argument.err, "mbd: error:")) << missing_argument.err;
    // a scene that does not exist
    const auto missing = run_mbd("check /nonexistent/scene.yaml");
    EXPECT_NE(missing.exit_code, 0);
    EXPECT_TRUE(contains(missing.err, "mbd: error:")) << missing.err;
}

TEST(Cli, CheckListsTheModel) {
    const auto r = run_mbd("check " + book_scene("slider-crank.yaml"));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    for (const char* part : {"bodies (3):", "crank", "rod", "slider", "joints (4):", "revolute", "prismatic",
                             "drivers (1):", "motor", "forces ("})
        EXPECT_TRUE(contains(r.out, part)) << part << "\n" << r.out;
}

TEST(Cli, BadSceneExitsWithTwoAndAnError) {
    const fs::path dir = scratch("bad_scene");
    const fs::path scene = dir / "bad.yaml";
    std::ofstream(scene) << "dimension: planar\nbodies:\n  - {name: b, mass: 1, inertia: 1, position: [0, 0], colour: red}\n";
    const fs::path out = dir / "out.csv";
    const auto r = run_mbd("kinematics " + scene.string() + " --t-end 1 --step 0.1 --output " + out.string());
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_TRUE(contains(r.err, "mbd: error:")) << r.err;
    EXPECT_TRUE(contains(r.err, "error")) << r.err;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_FALSE(fs::exists(out.string() + ".partial"));
    const auto check = run_mbd("check " + scene.string());
    EXPECT_EQ(check.exit_code, 2);
    EXPECT_TRUE(contains(check.err, "mbd: error:")) << check.err;
    // bad command-line values
    EXPECT_EQ(run_mbd("kinematics " + book_scene("slider-crank.yaml") + " --t-end 1 --step 0").exit_code, 2);
    EXPECT_EQ(run_mbd("kinematics " + book_scene("slider-crank.yaml") + " --step 0.1").exit_code, 2);
    fs::remove_all(dir);
}

TEST(Cli, KinematicsWritesTheCsvContract) {
    const fs::path dir = scratch("csv");
    const fs::path out = dir / "slider.csv";
    const auto r = run_mbd("kinematics " + book_scene("slider-crank.yaml") + " --t-end 0.124 --step 0.004 --output " +
                           out.string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    ASSERT_TRUE(fs::exists(out));
    EXPECT_FALSE(fs::exists(out.string() + ".partial"));
    const auto rows = lines(read_text(out));
    ASSERT_EQ(rows.size(), 33u);  // header + 32 samples
    EXPECT_EQ(rows[0],
              "t,crank.x,crank.y,crank.angle,rod.x,rod.y,rod.angle,slider.x,slider.y,slider.angle,"
              "crank.vx,crank.vy,crank.omega,rod.vx,rod.vy,rod.omega,slider.vx,slider.vy,slider.omega");
    for (size_t k = 1; k < rows.size(); ++k) {
        const auto cells = split(rows[k], ',');
        ASSERT_EQ(cells.size(), 19u) << rows[k];
        for (const auto& c : cells) EXPECT_TRUE(std::isfinite(std::strtod(c.c_str(), nullptr))) << rows[k];
    }
    // first and last samples against book Table 3.1: th2 = 0: x_B = 0.600, thdot3 = -25.0;
    // th2 = 6.2: th3 = 0.0416, x_B = 0.599, thdot3 = -24.9
    const auto first = split(rows[1], ',');
    EXPECT_DOUBLE_EQ(std::strtod(first[0].c_str(), nullptr), 0.0);
    EXPECT_NEAR(std::strtod(first[7].c_str(), nullptr), 0.600, 1e-3);
    EXPECT_NEAR(std::strtod(first[15].c_str(), nullptr), -25.0, 0.1);
    EXPECT_NEAR(std::strtod(first[12].c_str(), nullptr), 50.0, 1e-9);
    const auto last = split(rows.back(), ',');
    EXPECT_DOUBLE_EQ(std::strtod(last[0].c_str(), nullptr), 0.124);
    EXPECT_NEAR(std::strtod(last[6].c_str(), nullptr), 0.0416, 1e-4);
    EXPECT_NEAR(std::strtod(last[7].c_str(), nullptr), 0.599, 1e-3);
    EXPECT_NEAR(std::strtod(last[15].c_str(), nullptr), -24.9, 0.1);
    fs::remove_all(dir);
}

TEST(Cli, KinematicsSpatialColumnsAndTheLastSampleAtTEnd) {
    const fs::path dir = scratch("spatial");
    const fs::path out = dir / "rssr.csv";
    // 1.0 / 0.3 is not a whole number of steps: samples at 0, 0.3, 0.6, 0.9 and 1.0
    const auto r = run_mbd("kinematics " + book_scene("rssr.yaml") + " --t-end 1.0 --step 0.3 -o " + out.string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto rows = lines(read_text(out));
    ASSERT_EQ(rows.size(), 6u);
    const auto header = split(rows[0], ',');
    ASSERT_EQ(header.size(), 1u + 3 * 7 + 3 * 6);
    EXPECT_EQ(header[1], "crank.x");
    EXPECT_EQ(header[4], "crank.e0");
    EXPECT_EQ(header[7], "crank.e3");
    EXPECT_EQ(header[22], "crank.vx");
    EXPECT_EQ(header[25], "crank.wx");
    EXPECT_EQ(header[27], "crank.wz");
    EXPECT_EQ(header.back(), "rocker.wz");
    EXPECT_DOUBLE_EQ(std::strtod(split(rows.back(), ',')[0].c_str(), nullptr), 1.0);
    // the crank turns about world z at the driver's 1 rad/s
    EXPECT_NEAR(std::strtod(split(rows[2], ',')[27].c_str(), nullptr), 1.0, 1e-9);
    fs::remove_all(dir);
}

TEST(Cli, KinematicsWithoutOutputPrintsATable) {
    const auto r = run_mbd("kinematics " + book_scene("four-bar-table32.yaml") + " --t-end 0.124 --step 0.004");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(contains(r.out, "coupler.angle")) << r.out;
    EXPECT_TRUE(contains(r.out, "0.124")) << r.out;
}

TEST(Cli, FailedKinematicsLeavesNoFile) {
    const fs::path dir = scratch("failure");
    // the slider crank driven at its slider, beyond the reach l2 + l3 = 0.6 of the linkage
    std::string yaml = read_text(book_scene("slider-crank.yaml"));
    const auto at = yaml.find("    joint: O");
    ASSERT_NE(at, std::string::npos);
    yaml.replace(at, std::string("    joint: O").size(), "    joint: guide");
    const auto motion = yaml.find("{type: linear, initial: 0.0, rate: 50.0}");
    ASSERT_NE(motion, std::string::npos);
    yaml.replace(motion, std::string("{type: linear, initial: 0.0, rate: 50.0}").size(),
                 "{type: linear, initial: 0.5, rate: 0.0}");
    const fs::path scene = dir / "unreachable.yaml";
    std::ofstream(scene) << yaml;
    const fs::path out = dir / "out.csv";
    const auto r = run_mbd("kinematics " + scene.string() + " --t-end 0.1 --step 0.01 --output " + out.string());
    EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
    EXPECT_TRUE(contains(r.err, "mbd: error:")) << r.err;
    EXPECT_TRUE(contains(r.err, "assembly failed")) << r.err;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_FALSE(fs::exists(out.string() + ".partial"));
    // `mbd check` assembles too, and fails the same way
    const auto check = run_mbd("check " + scene.string());
    EXPECT_EQ(check.exit_code, 1);
    EXPECT_TRUE(contains(check.err, "mbd: error:")) << check.err;
    fs::remove_all(dir);
}

TEST(CsvWriter, WritesAPartialFileRenamesOnCloseAndRefusesNaN) {
    const fs::path dir = scratch("writer");
    const fs::path path = dir / "a.csv";
    {
        mbd::CsvWriter writer(path.string(), {"t", "x"});
        writer.row({0.0, 0.1});
        EXPECT_TRUE(fs::exists(path.string() + ".partial"));
        EXPECT_FALSE(fs::exists(path));
        EXPECT_THROW(writer.row({0.1, std::nan("")}), std::runtime_error);
        EXPECT_THROW(writer.row({0.1, HUGE_VAL}), std::runtime_error);
        EXPECT_THROW(writer.row({0.1}), std::exception);
        writer.row({0.1, 1.0 / 3.0});
        writer.close();
    }
    EXPECT_FALSE(fs::exists(path.string() + ".partial"));
    EXPECT_EQ(read_text(path), "t,x\n0,0.10000000000000001\n0.10000000000000001,0.33333333333333331\n");
    // not closed (an error interrupted the run): nothing under the final name, the
    // complete rows in the partial file (the output contract, mbd/output_file.hpp)
    const fs::path other = dir / "b.csv";
    {
        mbd::CsvWriter writer(other.string(), {"t"});
        writer.row({0.0});
    }
    EXPECT_FALSE(fs::exists(other));
    EXPECT_EQ(read_text(other.string() + ".partial"), "t\n0\n");
    fs::remove_all(dir);
}

}  // namespace
