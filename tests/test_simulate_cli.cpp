// `mbd simulate`: the CSV contract with reaction and diagnostics columns, and an unknown
// formulation (lists the known ones, non-zero exit). A failing run (exit 1, its rows in
// OUT.partial) is in tests/test_output_contract.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

#include "support/test_support.hpp"

namespace {

using mbd::test::Csv;
using mbd::test::read_csv;
using mbd::test::scratch;

namespace fs = std::filesystem;
using mbd::test::run_mbd;

std::string scene(const std::string& relative) { return mbd::test::scene_path(relative).string(); }

std::vector<std::string> split(const std::string& line, char sep) {
    std::vector<std::string> out;
    std::stringstream s(line);
    std::string item;
    while (std::getline(s, item, sep)) out.push_back(item);
    return out;
}

// Parse a CSV; every row must have the header's number of finite numbers.
bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(SimulateCli, WritesTheCsvContractWithReactionsAndDiagnostics) {
    const fs::path dir = scratch("contract");
    const fs::path out = dir / "pendulum.csv";
    const auto r = run_mbd("simulate " + scene("dynamics/pendulum-a01.yaml") +
                           " --integrator dopri5 --tol 1e-10 --t-end 2 --output-step 0.01 --reactions --diagnostics -o " +
                           out.string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    // no formulation named and none in the scene: the automatic choice for a tree
    EXPECT_TRUE(contains(r.out, "formulation embedding")) << r.out;
    EXPECT_TRUE(contains(r.err, "formulation embedding (automatic: tree of 1 joint")) << r.err;
    EXPECT_TRUE(contains(r.out, "integrator dopri5")) << r.out;
    EXPECT_TRUE(contains(r.out, "rejected")) << r.out;
    EXPECT_TRUE(contains(r.out, "CPU time")) << r.out;
    EXPECT_TRUE(contains(r.out, "final constraint violation")) << r.out;
    EXPECT_FALSE(fs::exists(out.string() + ".partial"));

    const Csv csv = read_csv(out);
    const std::vector<std::string> expected{"t", "bob.x", "bob.y", "bob.angle", "bob.vx", "bob.vy", "bob.omega",
                                            "pivot.fx", "pivot.fy", "pivot.tz", "kinetic_energy", "potential_energy",
                                            "constraint_position_violation", "constraint_velocity_violation"};
    EXPECT_EQ(csv.header, expected);
    ASSERT_EQ(csv.rows.size(), 201u);
    EXPECT_DOUBLE_EQ(csv.rows.front()[0], 0.0);
    EXPECT_DOUBLE_EQ(csv.rows.back()[0], 2.0);

    // the pin force on the bob: radial balance F . e = m v^2 / l - m g . e, no moment at
    // the pin; T + V conserved; the constraints hold
    const double E0 = csv.rows[0][10] + csv.rows[0][11];
    double radial = 0.0, moment = 0.0, energy = 0.0, violation = 0.0, peak = 0.0;
    for (const auto& row : csv.rows) {
        const double x = row[1], y = row[2], vx = row[4], vy = row[5], fx = row[7], fy = row[8];
        const double l = std::hypot(x, y), ex = -x / l, ey = -y / l;
        const double expected_radial = (vx * vx + vy * vy) / l - (-9.81 * ey);
        radial = std::max(radial, std::abs(fx * ex + fy * ey - expected_radial));
        moment = std::max(moment, std::abs(row[9]));
        energy = std::max(energy, std::abs(row[10] + row[11] - E0));
        violation = std::max({violation, row[12], row[13]});
        peak = std::max(peak, std::hypot(fx, fy));
    }
    EXPECT_LT(radial, 1e-5);
    EXPECT_LT(moment, 1e-12);
    EXPECT_LT(energy, 1e-8);
    EXPECT_LT(violation, 1e-10);
    EXPECT_NEAR(peak, 3 * 9.81, 1e-2);  // 3 m g at the bottom of the swing (sampled every 0.01 s)
}

TEST(SimulateCli, SpatialReactionColumns) {
    const fs::path dir = scratch("spatial");
    const fs::path out = dir / "top.csv";
    const auto r = run_mbd("simulate " + scene("dynamics/heavy-top.yaml") +
                           " --integrator dopri5 --tol 1e-11 --t-end 0.1 --output-step 0.05 --reactions -q -o " + out.string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const Csv csv = read_csv(out);
    ASSERT_EQ(csv.header.size(), 1u + 7 + 6 + 6);
    EXPECT_EQ(csv.header[14], "O.fx");
    EXPECT_EQ(csv.header[19], "O.tz");
    EXPECT_EQ(csv.rows.size(), 3u);
    // steady precession: the pin carries the weight, m g = 9.81 along +z
    for (const auto& row : csv.rows) EXPECT_NEAR(row[16], 9.81, 1e-6);
}

TEST(SimulateCli, UnknownFormulationListsTheKnownOnes) {
    const fs::path dir = scratch("unknown");
    const auto r = run_mbd("simulate " + scene("dynamics/pendulum-a01.yaml") + " --formulation lagrangian_magic --t-end 1 -o " +
                           (dir / "x.csv").string());
    EXPECT_NE(r.exit_code, 0);
    EXPECT_TRUE(contains(r.err, "mbd: error:")) << r.err;
    EXPECT_TRUE(contains(r.err, "lagrangian_magic")) << r.err;
    EXPECT_TRUE(contains(r.err, "augmented")) << r.err;
    EXPECT_FALSE(fs::exists(dir / "x.csv"));
}

TEST(SimulateCli, StabilizationAndLinearAlgebraOptions) {
    const fs::path dir = scratch("options");
    for (const char* stabilization : {"projection", "baumgarte", "none"}) {
        const auto r = run_mbd("simulate " + scene("dynamics/four-bar-spring-damper.yaml") +
                               " --tol 1e-8 --t-end 0.2 --linear-algebra sparse --stabilization " + stabilization +
                               " -q -o " + (dir / (std::string(stabilization) + ".csv")).string());
        EXPECT_EQ(r.exit_code, 0) << stabilization << ": " << r.err;
    }
    const auto bad = run_mbd("simulate " + scene("dynamics/four-bar-spring-damper.yaml") +
                             " --t-end 0.2 --stabilization sometimes -o " + (dir / "bad.csv").string());
    EXPECT_EQ(bad.exit_code, 2);
}

}  // namespace
