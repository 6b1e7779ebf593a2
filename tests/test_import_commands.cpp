// Issue 37, a model file wherever a scene is accepted: `mbd sweep` (the study's `scene:`) and
// `mbd stability` (its SCENE arguments) take an MJCF, URDF or SDF file (docs/import.md).
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace mbd::test {
namespace {

namespace fs = std::filesystem;

std::string quoted(const fs::path& p) { return "'" + p.string() + "'"; }

// A pendulum in URDF: the bob (1 kg, centroidal moments 1e-6 kg m^2) 0.5 m along x from a
// hinge about y at the origin, released at rest from the horizontal (URDF's gravity: 9.81 down
// -z), and a visual mesh that is missing (one warning).
const char* kPendulum = R"(<?xml version="1.0"?>
<robot name="pendulum">
  <link name="base"/>
  <link name="bob">
    <inertial><origin xyz="0.5 0 0"/><mass value="1"/><inertia ixx="1e-6" ixy="0" ixz="0" iyy="1e-6" iyz="0" izz="1e-6"/></inertial>
    <visual><geometry><mesh filename="package://nowhere/bob.stl"/></geometry></visual>
  </link>
  <joint name="pivot" type="continuous"><parent link="base"/><child link="bob"/><axis xyz="0 1 0"/></joint>
</robot>
)";

std::vector<std::vector<double>> csv_rows(const fs::path& file, std::vector<std::string>& header) {
    std::ifstream in(file);
    std::string line, cell;
    std::getline(in, line);
    std::stringstream h(line);
    while (std::getline(h, cell, ',')) header.push_back(cell);
    std::vector<std::vector<double>> rows;
    while (std::getline(in, line)) {
        std::stringstream r(line);
        rows.emplace_back();
        while (std::getline(r, cell, ',')) rows.back().push_back(std::strtod(cell.c_str(), nullptr));
    }
    return rows;
}

int column(const std::vector<std::string>& header, const std::string& name) {
    for (size_t k = 0; k < header.size(); ++k)
        if (header[k] == name) return static_cast<int>(k);
    ADD_FAILURE() << "no column " << name;
    return 0;
}

// The study names the URDF as its scene and varies the imported bob's distance L from the
// hinge (its mass centre's x). Energy: at the bottom the bob turns at
// omega = sqrt(2 m g L / (m L^2 + I)) about +y, the fastest of its swing (within the first
// second: a quarter period is at most 0.47 s here).
TEST(ImportCommands, SweepTakesAModelFileAsTheStudysScene) {
    const fs::path dir = scratch("import_commands_sweep");
    write_text(dir / "pendulum.urdf", kPendulum);
    write_text(dir / "study.yaml", "scene: pendulum.urdf\n"
                                   "analysis: {type: simulate, t_end: 1, integrator: dopri5, tol: 1.0e-10, output_step: 0.0005}\n"
                                   "parameters:\n  - {path: \"bodies.bob.position[0]\", values: [0.3, 0.6]}\n"
                                   "design: {type: grid}\n"
                                   "metrics:\n  - max: bob.wy\n");
    const CommandResult r = run_mbd("sweep " + quoted(dir / "study.yaml") + " -o " + quoted(dir / "r.h5") + " --csv " +
                                    quoted(dir / "t.csv") + " -q --threads 1");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("visual meshes not found"), std::string::npos) << r.err;  // the import's one warning
    std::vector<std::string> header;
    const auto rows = csv_rows(dir / "t.csv", header);
    ASSERT_EQ(rows.size(), 2u);
    const int length = column(header, "bodies.bob.position[0]"), omega = column(header, "max(bob.wy)");
    for (const auto& row : rows) {
        const double L = row[length], expected = std::sqrt(2.0 * 9.81 * L / (L * L + 1e-6));
        SCOPED_TRACE("L = " + std::to_string(L));
        EXPECT_NEAR(row[omega], expected, 1e-4 * expected);  // the 0.5 ms sampling of the maximum
    }
}

// `mbd stability MODEL`: the model declares no outcome, so it is run as `expect: {outcome:
// pass}` (its constraints held to 1e-6 over 1 s by the declared pair, augmented with dopri5).
// The import's warning comes once (the runs' children are quiet); a file that is neither a
// scene nor a model file the import can read is bad input.
TEST(ImportCommands, StabilityTakesAModelFile) {
    const fs::path dir = scratch("import_commands_stability");
    write_text(dir / "pendulum.urdf", kPendulum);
    const CommandResult r = run_mbd("stability " + quoted(dir / "pendulum.urdf") +
                                    " --formulation augmented --formulation embedding --integrator dopri5 -q --markdown " +
                                    quoted(dir / "m.md"));
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    for (const char* formulation : {"augmented", "embedding"}) {
        char cell[128];
        std::snprintf(cell, sizeof cell, "%-28s %-12s %-18s pass", "pendulum", formulation, "dopri5");
        EXPECT_NE(r.out.find(cell), std::string::npos) << cell << "\n" << r.out;
    }
    EXPECT_NE(r.out.find("1 cases: 0 declared pairs missed their declared outcome, 0 crashes or errors"), std::string::npos)
        << r.out;
    size_t warnings = 0;
    for (size_t at = r.err.find("visual meshes not found"); at != std::string::npos; at = r.err.find("visual meshes not found", at + 1))
        ++warnings;
    EXPECT_EQ(warnings, 1u) << r.err;
    EXPECT_TRUE(fs::exists(dir / "m.md"));

    write_text(dir / "broken.urdf", "<robot name=\"broken\"><link name=\"a\"></robot>");
    const CommandResult bad = run_mbd("stability " + quoted(dir / "broken.urdf") + " -q --markdown " + quoted(dir / "b.md"));
    EXPECT_EQ(bad.exit_code, 2) << bad.err;
    EXPECT_NE(bad.err.find("broken.urdf"), std::string::npos) << bad.err;
    EXPECT_FALSE(fs::exists(dir / "b.md"));
}

}  // namespace
}  // namespace mbd::test
