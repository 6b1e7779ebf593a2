// `mbd bench MODEL.urdf` (cli/bench_model_file.hpp, docs/benchmarks.md "Model files"): one URDF
// run by mbd (imported), by MuJoCo and by DART, each reading the file itself. The oracle is the
// agreement of three independent engines, each converging at its own method's order to mbd's
// tight reference: MuJoCo's RK4 to below 1e-8, DART's semi-implicit Euler at order 1.
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <map>

namespace mbd {
namespace {

// A double pendulum hanging from a world link (axes along y, gravity -z), with a massless tool
// link welded to the second link: merged by every engine, so not measured.
const char* kDoublePendulum = R"(<?xml version="1.0"?>
<robot name="double_pendulum">
  <link name="world"/>
  <link name="link1">
    <inertial><origin xyz="0 0 -0.25"/><mass value="1.0"/>
      <inertia ixx="0.02" ixy="0.001" ixz="0" iyy="0.021" iyz="0" izz="0.003"/></inertial>
    <visual><geometry><mesh filename="package://missing/link1.stl"/></geometry></visual>
  </link>
  <link name="link2">
    <inertial><origin xyz="0.02 0 -0.2"/><mass value="0.7"/>
      <inertia ixx="0.01" ixy="0" ixz="0.0005" iyy="0.011" iyz="0" izz="0.002"/></inertial>
  </link>
  <link name="tool"/>
  <joint name="j1" type="revolute"><parent link="world"/><child link="link1"/>
    <origin xyz="0 0 1" rpy="0.3 0 0"/><axis xyz="0 1 0"/><limit lower="-10" upper="10" effort="1" velocity="100"/></joint>
  <joint name="j2" type="continuous"><parent link="link1"/><child link="link2"/>
    <origin xyz="0 0 -0.5"/><axis xyz="0 1 0"/></joint>
  <joint name="tool_mount" type="fixed"><parent link="link2"/><child link="tool"/><origin xyz="0 0 -0.4"/></joint>
</robot>
)";

struct Series {
    std::vector<double> steps, errors;
};

// `mbd bench URDF`: the measure's text and the peers' error series by engine, every row ok.
std::map<std::string, Series> bench_peers(const std::string& name, const std::string& urdf_text, std::string& measure,
                                          double& mbd_best) {
    const auto dir = test::scratch("bench_model_file");
    const auto urdf = test::write_text(dir / name, urdf_text);
    const auto json = dir / "b.json";
    const auto r = test::run_mbd("bench " + urdf.string() + " --repeat 1 -q --min-tol 1e-9 --csv " +
                                 (dir / "b.csv").string() + " --json " + json.string());
    EXPECT_EQ(r.exit_code, 0) << r.err;
    if (r.exit_code != 0) return {};
    const auto doc = nlohmann::json::parse(test::read_text(json));
    EXPECT_EQ(doc["scenes"].size(), 1u);
    measure = doc["scenes"][0]["error_measure"];
    std::map<std::string, Series> peers;
    mbd_best = 1.0;
    for (const auto& row : doc["rows"]) {
        const std::string engine = row["engine"];
        EXPECT_EQ(row["status"], "ok") << engine << " " << row.dump();
        if (row["status"] != "ok") continue;
        if (engine == "mbd") mbd_best = std::min(mbd_best, row["error"].get<double>());
        else {  // by engine and integrator: "mujoco rk4", "dart euler", "dart rk4"
            Series& series = peers[engine + " " + row["integrator"].get<std::string>()];
            series.steps.push_back(row["step"]), series.errors.push_back(row["error"]);
        }
    }
    return peers;
}

// MuJoCo's RK4 and RK4 over DART's forward dynamics reach mbd's reference (same bodies,
// inertias, velocities) at fourth order; DART's World (semi-implicit Euler) converges to it at
// order 1 (sqrt(10) per half decade of step).
void expect_peers_converge_to_mbd(std::map<std::string, Series>& peers) {
    for (const char* fourth_order : {"mujoco rk4", "dart rk4"}) {
        const auto& e = peers[fourth_order].errors;
        ASSERT_EQ(e.size(), 7u) << fourth_order;  // steps 1e-2 to 1e-5, two per decade
        EXPECT_LT(*std::min_element(e.begin(), e.end()), 1e-8) << fourth_order;
        EXPECT_GT(e[0] / e[1], 30.0) << fourth_order;  // fourth order: 100 per half decade of step
    }
    ASSERT_EQ(peers["dart euler"].errors.size(), 7u);
    const auto& dart = peers["dart euler"].errors;
    for (size_t k = 3; k + 1 < dart.size(); ++k) {
        EXPECT_GT(dart[k] / dart[k + 1], 2.5) << "step " << peers["dart euler"].steps[k];
        EXPECT_LT(dart[k] / dart[k + 1], 4.0) << "step " << peers["dart euler"].steps[k];
    }
    EXPECT_LT(dart.back(), 1e-5);
}

TEST(BenchModelFile, UrdfRunsInMuJoCoAndDartFromTheSameFile) {
    std::string measure;
    double mbd_best = 1.0;
    auto peers = bench_peers("double_pendulum.urdf", kDoublePendulum, measure, mbd_best);
    EXPECT_NE(measure.find("link1, link2"), std::string::npos) << measure;  // tool merged, world the ground
    EXPECT_EQ(measure.find("tool"), std::string::npos) << measure;
    EXPECT_LT(mbd_best, 1e-8);
    expect_peers_converge_to_mbd(peers);
}

// A root link without a parent joint is fixed to the world in URDF, MuJoCo and mbd; DART's
// reader would let it float (the peer sets it fixed).
TEST(BenchModelFile, UrdfRootLinkIsFixedInEveryEngine) {
    std::string text = kDoublePendulum;
    text = test::replaced(text, "<link name=\"world\"/>", "");
    const size_t j1 = text.find("<joint name=\"j1\""), end = text.find("</joint>", j1);
    text.erase(j1, end + 8 - j1);
    std::string measure;
    double mbd_best = 1.0;
    auto peers = bench_peers("rooted_pendulum.urdf", text, measure, mbd_best);
    EXPECT_NE(measure.find("link2"), std::string::npos) << measure;
    expect_peers_converge_to_mbd(peers);
}

}  // namespace
}  // namespace mbd
