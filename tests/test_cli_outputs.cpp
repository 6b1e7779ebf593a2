// What the mbd command prints and writes, against oracles that do not come from mbd: the
// mobility counts of `mbd check` (Gruebler's formula by hand, the Bricard's known one degree of
// freedom), the table of `mbd kinematics` against the closed-form four-bar position analysis, the
// CSVs of `mbd simulate` under every stabilization and linear algebra against each other and
// against the constraints, and the option named in each refusal of a bad command-line value.
// (The exit codes of the same commands are tested in test_cli.cpp and test_simulate_cli.cpp.)
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "support/test_support.hpp"

namespace {

namespace fs = std::filesystem;
using mbd::test::Csv;
using mbd::test::read_csv;
using mbd::test::run_mbd;
using mbd::test::scratch;

std::string scene(const std::string& relative) { return mbd::test::scene_path(relative).string(); }
bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// The line of `text` that starts with `prefix` (empty when none).
std::string line_starting(const std::string& text, const std::string& prefix) {
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line))
        if (line.rfind(prefix, 0) == 0) return line;
    return {};
}

TEST(CliOutputs, CheckCountsTheDegreesOfFreedom) {
    // slider crank (book Sec. 3.9): 3 bodies x 3 - 3 revolutes x 2 - 1 prismatic x 2 = 1 DOF,
    // which its one driver fixes
    const auto crank = run_mbd("check " + scene("book/slider-crank.yaml"));
    ASSERT_EQ(crank.exit_code, 0) << crank.err;
    EXPECT_EQ(line_starting(crank.out, "degrees of freedom (Gruebler count):"), "degrees of freedom (Gruebler count): 1")
        << crank.out;
    EXPECT_TRUE(contains(line_starting(crank.out, "degrees of freedom (rank of C_q):"), ": 1 ")) << crank.out;
    EXPECT_TRUE(contains(line_starting(crank.out, "kinematically driven:"), "yes")) << crank.out;
    EXPECT_TRUE(contains(crank.out, "assembled at t = 0")) << crank.out;
    // Bricard (book Sec. 3.11): 5 moving links x 6 - 6 revolutes x 5 = 0 by Gruebler, yet it
    // moves with 1 DOF: one row is redundant and is named
    const auto bricard = run_mbd("check " + scene("book/bricard.yaml"));
    ASSERT_EQ(bricard.exit_code, 0) << bricard.err;
    EXPECT_EQ(line_starting(bricard.out, "degrees of freedom (Gruebler count):"), "degrees of freedom (Gruebler count): 0")
        << bricard.out;
    EXPECT_TRUE(contains(line_starting(bricard.out, "degrees of freedom (rank of C_q):"), ": 1 ")) << bricard.out;
    EXPECT_TRUE(contains(bricard.out, "redundant constraint rows (1):")) << bricard.out;
}

// Coupler angle of the four-bar of book Table 3.2 (l1 = 0.4 ground, l2 = 0.2 crank, l3 = 0.4
// coupler, l4 = 0.5 rocker; O = (0, 0), C = (0.4, 0)) at crank angle th2, by intersecting the
// circle of radius l3 about A with the circle of radius l4 about C, on the branch of the scene's
// initial configuration (B above the line AC).
double four_bar_coupler_angle(double th2) {
    const double l3 = 0.4, l4 = 0.5;
    const double ax = 0.2 * std::cos(th2), ay = 0.2 * std::sin(th2), cx = 0.4, cy = 0.0;
    const double dx = cx - ax, dy = cy - ay, d = std::hypot(dx, dy);
    const double along = (l3 * l3 - l4 * l4 + d * d) / (2 * d);  // from A towards C
    const double across = std::sqrt(l3 * l3 - along * along);
    const double bx = ax + along * dx / d - across * dy / d, by = ay + along * dy / d + across * dx / d;
    return std::atan2(by - ay, bx - ax);
}

TEST(CliOutputs, KinematicsTableMatchesTheClosedFormFourBar) {
    const auto r = run_mbd("kinematics " + scene("book/four-bar-table32.yaml") + " --t-end 0.124 --step 0.004");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    // the table: a header line naming the columns, then one line per shown sample
    std::istringstream in(r.out);
    std::string line;
    std::vector<std::string> header;
    int coupler = -1, rows = 0;
    double last_t = -1.0;
    while (std::getline(in, line)) {
        std::istringstream cells(line);
        std::vector<std::string> words;
        for (std::string w; cells >> w;) words.push_back(w);
        if (words.empty()) continue;
        if (words[0] == "t") {
            if (!header.empty()) break;  // the next block of columns
            header = words;
            for (size_t k = 0; k < words.size(); ++k)
                if (words[k] == "coupler.angle") coupler = static_cast<int>(k);
            continue;
        }
        if (header.empty() || coupler < 0 || words.size() != header.size()) continue;
        const double t = std::stod(words[0]), angle = std::stod(words[coupler]);
        const double exact = four_bar_coupler_angle(M_PI / 2 + 50 * t);
        // the table prints 8 significant digits; the angle may differ by whole turns
        EXPECT_NEAR(std::remainder(angle - exact, 2 * M_PI), 0.0, 1e-7) << "t = " << t << ": " << line;
        last_t = t;
        ++rows;
    }
    ASSERT_GE(coupler, 0) << r.out;
    EXPECT_GE(rows, 5) << r.out;
    EXPECT_DOUBLE_EQ(last_t, 0.124) << "the last row is t_end\n" << r.out;
}

TEST(CliOutputs, EveryStabilizationAndLinearAlgebraGivesTheSameMotion) {
    // the four-bar with a spring-damper, 0.2 s at tol 1e-9: the three stabilizations and the two
    // linear algebras integrate the same ODE on the constraint manifold, so their final rows agree
    // to about the tolerance, and the constraints hold (projection: to round-off)
    const fs::path dir = scratch("stabilizations");
    std::vector<std::vector<double>> finals;
    for (const char* algebra : {"dense", "sparse"})
        for (const char* stabilization : {"projection", "baumgarte", "none"}) {
            const std::string name = std::string(stabilization) + "-" + algebra;
            const fs::path out = dir / (name + ".csv");
            const auto r = run_mbd("simulate " + scene("dynamics/four-bar-spring-damper.yaml") +
                                   " --tol 1e-9 --t-end 0.2 --output-step 0.1 --diagnostics --linear-algebra " + algebra +
                                   " --stabilization " + stabilization + " -q -o " + out.string());
            ASSERT_EQ(r.exit_code, 0) << name << ": " << r.err;
            const Csv csv = read_csv(out);
            ASSERT_EQ(csv.rows.size(), 3u) << name;
            EXPECT_DOUBLE_EQ(csv.rows.back()[0], 0.2) << name;
            const int violation = csv.column("constraint_position_violation");
            ASSERT_GE(violation, 0) << name;
            for (const auto& row : csv.rows)
                EXPECT_LT(row[violation], std::string(stabilization) == "projection" ? 1e-10 : 1e-6) << name;
            finals.push_back(csv.rows.back());
        }
    for (size_t k = 1; k < finals.size(); ++k)
        for (size_t c = 1; c < finals[0].size(); ++c)
            EXPECT_NEAR(finals[k][c], finals[0][c], 1e-6 * std::max(1.0, std::abs(finals[0][c]))) << "run " << k << " column " << c;
    // a value that is not a stabilization names the option and the accepted values
    const auto bad = run_mbd("simulate " + scene("dynamics/four-bar-spring-damper.yaml") +
                             " --t-end 0.2 --stabilization sometimes -o " + (dir / "bad.csv").string());
    EXPECT_EQ(bad.exit_code, 2);
    EXPECT_TRUE(contains(bad.err, "--stabilization")) << bad.err;
    EXPECT_TRUE(contains(bad.err, "projection")) << bad.err;
    EXPECT_FALSE(fs::exists(dir / "bad.csv"));
    fs::remove_all(dir);
}

TEST(CliOutputs, BadCommandLineValuesNameTheOption) {
    const fs::path dir = scratch("bad_values");
    const std::string crank = scene("book/slider-crank.yaml");
    struct Case {
        std::string arguments;
        std::string option;  // named in the error
    };
    const std::vector<Case> cases = {
        {"kinematics " + crank + " --t-end 1 --step 0", "--step"},
        {"kinematics " + crank + " --step 0.1", "--t-end"},
        {"kinematics " + crank + " --t-end 1 --step -0.1", "--step"},
        {"simulate " + scene("dynamics/pendulum-a01.yaml") + " --t-end 1 --tol -1", "--tol"},
    };
    for (const Case& c : cases) {
        const fs::path out = dir / "out.csv";
        const auto r = run_mbd(c.arguments + " -o " + out.string());
        EXPECT_EQ(r.exit_code, 2) << c.arguments << "\n" << r.err;
        EXPECT_TRUE(contains(r.err, "mbd: error:")) << c.arguments << "\n" << r.err;
        EXPECT_TRUE(contains(r.err, c.option)) << c.arguments << ": the error must name " << c.option << "\n" << r.err;
        EXPECT_FALSE(fs::exists(out)) << c.arguments;
        EXPECT_FALSE(fs::exists(out.string() + ".partial")) << c.arguments;
    }
    fs::remove_all(dir);
}

TEST(CliOutputs, SimulateSummaryReportsTheRunItDid) {
    // the pendulum A01 for 1 s: the summary names the formulation and integrator, the rows written
    // and the file; the file's last row is at t_end and its first row is the scene's initial state
    const fs::path dir = scratch("summary");
    const fs::path out = dir / "a01.csv";
    const auto r = run_mbd("simulate " + scene("dynamics/pendulum-a01.yaml") +
                           " --formulation embedding --integrator rk4 --step 1e-3 --t-end 1 --output-step 0.25 -o " +
                           out.string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(contains(r.out, "formulation embedding")) << r.out;
    EXPECT_TRUE(contains(r.out, "integrator rk4")) << r.out;
    EXPECT_TRUE(contains(r.out, out.string())) << r.out;
    const Csv csv = read_csv(out);
    ASSERT_EQ(csv.rows.size(), 5u);
    EXPECT_TRUE(contains(r.out, "5 rows")) << "the number of rows written\n" << r.out;
    const mbd::Model model = mbd::test::load("dynamics/pendulum-a01.yaml");
    const mbd::State initial = model.initial_state();
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(csv.rows.front()[1 + k], initial.q[k], 1e-9) << k;
    EXPECT_DOUBLE_EQ(csv.rows.back()[0], 1.0);
    // the pendulum keeps its length (the pivot at the origin)
    const double length = std::hypot(csv.rows.front()[1], csv.rows.front()[2]);
    for (const auto& row : csv.rows) EXPECT_NEAR(std::hypot(row[1], row[2]), length, 1e-9) << "t = " << row[0];
    fs::remove_all(dir);
}

}  // namespace
