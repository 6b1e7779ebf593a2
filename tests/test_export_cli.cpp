// Issue 37, `mbd export` (docs/import.md, "Export"): a scene written as MJCF that MuJoCo compiles
// into the same tree and as URDF that reads back; what a format cannot hold is named in one
// warning or refused with --strict; bad input exits 2 and writes nothing.
#include "support/mujoco_oracle.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

namespace mbd::test {
namespace {

namespace fs = std::filesystem;

std::string quoted(const fs::path& p) { return "'" + p.string() + "'"; }

TEST(ExportCli, ThePlanarChainBecomesFiveHingesInMuJoCoAndAUrdfThatLoads) {
    const fs::path dir = scratch("export_cli_chain");
    const CommandResult mjcf = run_mbd("export " + quoted(scene_path("bench/chain-5.yaml")) + " -o " + quoted(dir / "chain.xml"));
    ASSERT_EQ(mjcf.exit_code, 0) << mjcf.err;
    EXPECT_EQ(mjcf.err, "");
    MjModelPtr m = compile(dir / "chain.xml");
    ASSERT_TRUE(m);
    EXPECT_EQ(m->nbody, 6);  // the world and five links
    ASSERT_EQ(m->njnt, 5);
    for (int j = 0; j < m->njnt; ++j) {
        EXPECT_EQ(m->jnt_type[j], mjJNT_HINGE);
        EXPECT_NEAR(m->body_mass[j + 1], 1.0, 1e-15);
    }
    // link l0 hangs from the origin: its hinge is 0.05 m behind its mass centre along x
    EXPECT_NEAR(m->jnt_pos[0], -0.05, 1e-15);
    const CommandResult urdf = run_mbd("export " + quoted(scene_path("bench/chain-5.yaml")) + " -o " + quoted(dir / "chain.urdf"));
    ASSERT_EQ(urdf.exit_code, 0) << urdf.err;
    const CommandResult back = run_mbd("check " + quoted(dir / "chain.urdf"));
    EXPECT_EQ(back.exit_code, 0) << back.err;
}

TEST(ExportCli, WhatMjcfCannotHoldIsNamedInOneWarningOrRefusedWithStrict) {
    const fs::path dir = scratch("export_cli_left_out");
    const std::string scene = quoted(scene_path("four-bar.yaml"));
    const CommandResult warned = run_mbd("export " + scene + " -o " + quoted(dir / "four-bar.xml"));
    ASSERT_EQ(warned.exit_code, 0) << warned.err;
    EXPECT_NE(warned.err.find("not exported: "), std::string::npos) << warned.err;
    EXPECT_NE(warned.err.find("joints that close a loop (B)"), std::string::npos) << warned.err;
    EXPECT_NE(warned.err.find("spring (spring_damper)"), std::string::npos) << warned.err;
    EXPECT_EQ(std::count(warned.err.begin(), warned.err.end(), '\n'), 1) << "one warning line: " << warned.err;
    EXPECT_TRUE(fs::exists(dir / "four-bar.xml"));
    const CommandResult strict = run_mbd("export " + scene + " --strict -o " + quoted(dir / "strict.xml"));
    EXPECT_EQ(strict.exit_code, 2);
    EXPECT_NE(strict.err.find("--strict: the export would leave out"), std::string::npos) << strict.err;
    EXPECT_FALSE(fs::exists(dir / "strict.xml"));
    EXPECT_FALSE(fs::exists(dir / "strict.xml.partial"));
}

TEST(ExportCli, BadInputExitsTwoAndWritesNothing) {
    const fs::path dir = scratch("export_cli_bad");
    struct Case {
        std::string arguments, expected, output;
    };
    const Case cases[] = {
        {quoted(scene_path("bench/chain-5.yaml")) + " -o " + quoted(dir / "chain.txt"), "name the model file .xml", "chain.txt"},
        {quoted(dir / "missing.yaml") + " -o " + quoted(dir / "missing.xml"), "missing.yaml", "missing.xml"},
        {quoted(scene_path("examples/spatial-spherical.yaml")) + " -o " + quoted(dir / "ball.urdf"),
         "URDF has no ball joint: 'ball'", "ball.urdf"},
        // a driver beyond reach from t = 0: no start to export, named with the scene
        {quoted(scene_path("extreme/unreachable-driver.yaml")) + " -o " + quoted(dir / "unreachable.xml"),
         "unreachable-driver.yaml: cannot be exported: its initial state cannot be assembled (assembly failed", "unreachable.xml"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.arguments);
        const CommandResult r = run_mbd("export " + c.arguments);
        EXPECT_EQ(r.exit_code, 2) << r.err;
        EXPECT_NE(r.err.find(c.expected), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(dir / c.output));
        EXPECT_FALSE(fs::exists(dir / (c.output + ".partial")));
    }
}

}  // namespace
}  // namespace mbd::test
