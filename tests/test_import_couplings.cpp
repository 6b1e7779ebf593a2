// Issue 37, joint couplings imported as coordinate_coupling joints (import/src/scene_builder.cpp
// add_coupling; docs/import.md): URDF <mimic> and MJCF <equality joint=...>.
//
// The mechanism: two pendulums hanging from a fixed base on hinges about y, the second (follow)
// mimicking the first (lead) with multiplier k = -0.5: q_f = k q_l. With q = q_l the one
// coordinate (pendulum i: mass m_i, mass centre c_i below its pivot, moment I_i about it),
//     (I_1 + k^2 I_2) q'' = -m_1 g c_1 sin q - k m_2 g c_2 sin(k q),
// which the test integrates itself (RK4, h = 1e-4: its own error below 1e-12) as the oracle.
// MuJoCo is not the oracle of the exact coupling: its equality constraints are soft; how far its
// run is from the exact one (default solref, and made stiff) is measured and printed.
#include "support/mujoco_oracle.hpp"
#include "support/input_files.hpp"
#include "support/test_support.hpp"

#include <mbd/import/import.hpp>
#include <mbd/import/scene_writer.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>

namespace mbd::test {
namespace {

namespace fs = std::filesystem;

fs::path write_file(const std::string& name, const std::string& content) {
    return write_scratch_file("import_couplings", name, content);
}

constexpr double g = 9.81, k = -0.5, m1 = 1.0, c1 = 0.3, m2 = 0.5, c2 = 0.2;
constexpr double I1 = 0.01 + m1 * c1 * c1, I2 = 0.004 + m2 * c2 * c2;
constexpr double q0 = 0.4, w0 = 1.5;  // the leader's start: angle (rad) and rate (rad/s)

// The leader's angle every 0.01 s over 1 s from the reduced equation above (RK4).
std::vector<double> oracle_angles() {
    auto accel = [](double q) { return (-m1 * g * c1 * std::sin(q) - k * m2 * g * c2 * std::sin(k * q)) / (I1 + k * k * I2); };
    std::vector<double> out{q0};
    double q = q0, w = w0;
    const double h = 1e-4;
    for (int step = 1; step <= 10000; ++step) {
        const double k1q = w, k1w = accel(q);
        const double k2q = w + 0.5 * h * k1w, k2w = accel(q + 0.5 * h * k1q);
        const double k3q = w + 0.5 * h * k2w, k3w = accel(q + 0.5 * h * k2q);
        const double k4q = w + h * k3w, k4w = accel(q + h * k3q);
        q += h / 6 * (k1q + 2 * k2q + 2 * k3q + k4q);
        w += h / 6 * (k1w + 2 * k2w + 2 * k3w + k4w);
        if (step % 100 == 0) out.push_back(q);
    }
    return out;
}

const char* kUrdf = R"(<?xml version="1.0"?>
<robot name="mimic_pendulums">
  <link name="base"/>
  <link name="lead_link"><inertial><mass value="1"/><origin xyz="0 0 -0.3"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.002"/></inertial></link>
  <link name="follow_link"><inertial><mass value="0.5"/><origin xyz="0 0 -0.2"/>
    <inertia ixx="0.004" ixy="0" ixz="0" iyy="0.004" iyz="0" izz="0.001"/></inertial></link>
  <joint name="lead" type="revolute"><parent link="base"/><child link="lead_link"/><origin xyz="0 0 1"/>
    <axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="follow" type="continuous"><parent link="base"/><child link="follow_link"/><origin xyz="0.5 0 1"/>
    <axis xyz="0 1 0"/><mimic joint="LEADER" multiplier="-0.5"/></joint>
</robot>
)";

const char* kMjcf = R"(<mujoco model="coupled_pendulums">
  <option gravity="0 0 -9.81"/>
  <worldbody>
    <body name="lead_link" pos="0 0 1">
      <joint name="lead" type="hinge" axis="0 1 0"/>
      <inertial pos="0 0 -0.3" mass="1" diaginertia="0.01 0.01 0.002"/>
    </body>
    <body name="follow_link" pos="0.5 0 1">
      <joint name="follow" type="hinge" axis="0 1 0"/>
      <inertial pos="0 0 -0.2" mass="0.5" diaginertia="0.004 0.004 0.001"/>
    </body>
  </worldbody>
  <equality><joint name="mimic" joint1="follow" joint2="lead" polycoef="0 -0.5 0 0 0" SOLREF/></equality>
</mujoco>
)";

import::ImportOptions started() {
    import::ImportOptions o;
    o.joint_positions = {{"lead", q0}, {"follow", k * q0}};
    o.joint_velocities = {{"lead", {w0}}, {"follow", {k * w0}}};
    return o;
}

// The largest difference of mbd's two angles (each body's turn about y) from the oracle's.
double difference_from_oracle(const fs::path& file) {
    const import::ImportedScene scene = import::import_model(file, started());
    EXPECT_EQ(scene.couplings.size(), 1u);
    const Model model = load_scene_text(import::scene_yaml(scene), file.string(), shared_registry());
    const int lead = model.body_index("lead_link"), follow = model.body_index("follow_link");
    const std::vector<double> exact = oracle_angles();
    double worst = 0.0;
    for (const std::string formulation : {"embedding", "augmented"}) {
        const std::vector<Eigen::VectorXd> q = mbd_run(model, 1.0, 0.01, formulation);
        EXPECT_EQ(q.size(), exact.size());
        for (size_t s = 0; s < q.size() && s < exact.size(); ++s) {
            auto turn = [&](int b) { return 2.0 * std::atan2(q[s][7 * b + 5], q[s][7 * b + 3]); };
            worst = std::max({worst, std::abs(turn(lead) - exact[s]), std::abs(turn(follow) - k * exact[s])});
        }
    }
    return worst;
}

TEST(ImportCouplings, UrdfMimicFollowsTheReducedEquation) {
    const fs::path urdf = write_file("mimic.urdf", replaced(kUrdf, "LEADER", "lead"));
    const double worst = difference_from_oracle(urdf);
    std::printf("URDF mimic: mbd against the reduced equation %.2e rad over 1 s\n", worst);
    EXPECT_LT(worst, 1e-8);
}

TEST(ImportCouplings, MjcfJointEqualityFollowsTheReducedEquation) {
    const fs::path mjcf = write_file("coupled.xml", replaced(kMjcf, " SOLREF", ""));
    const double worst = difference_from_oracle(mjcf);
    std::printf("MJCF equality joint: mbd against the reduced equation %.2e rad over 1 s\n", worst);
    EXPECT_LT(worst, 1e-8);
}

// MuJoCo's soft equality against the exact coupling: the leader's angle from MuJoCo's RK4
// (h = 1e-4) with the default solref (0.02 s) and with a stiff one (0.001 s).
TEST(ImportCouplings, MuJoCosSoftEqualityApproachesTheExactCouplingWhenStiff) {
    const std::vector<double> exact = oracle_angles();
    double gap[2] = {0, 0};
    const char* solrefs[2] = {"", " solref=\"0.001 1\""};
    for (int c = 0; c < 2; ++c) {
        const fs::path file = write_file("soft" + std::to_string(c) + ".xml", replaced(kMjcf, " SOLREF", solrefs[c]));
        MjModelPtr m = compile(file);
        ASSERT_TRUE(m);
        const std::vector<std::vector<double>> q = [&] {
            std::vector<std::vector<double>> out;
            mujoco_samples(m.get(), {w0, k * w0}, 1e-4, 1.0, 0.01,
                           [&](const mjData* d) { out.emplace_back(d->qpos, d->qpos + 2); }, {q0, k * q0});
            return out;
        }();
        for (size_t s = 0; s < q.size() && s < exact.size(); ++s)
            gap[c] = std::max({gap[c], std::abs(q[s][0] - exact[s]), std::abs(q[s][1] - k * exact[s])});
    }
    std::printf("MuJoCo against the exact coupling over 1 s: default solref %.2e rad, solref 0.001 s %.2e rad\n", gap[0],
                gap[1]);
    EXPECT_LT(gap[1], gap[0]);
    EXPECT_LT(gap[1], 1e-5);
}

// Bad couplings: a mimic of a missing joint, a curved MJCF polycoef, a start that breaks the
// coupling; each exits 2 naming the element, and nothing is written.
TEST(ImportCouplings, BadCouplingsAreRefusedNamingTheElement) {
    const fs::path out = scratch("import_couplings_bad") / "scene.yaml";
    auto refused = [&](const fs::path& file, const std::string& extra, const std::string& message) {
        const CommandResult r = run_mbd("import " + file.string() + " -o " + out.string() + extra);
        EXPECT_EQ(r.exit_code, 2) << r.err;
        EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(out));
    };
    refused(write_file("missing.urdf", replaced(kUrdf, "LEADER", "nope")), "",
            "URDF joint 'follow' <mimic>: its leader joint 'nope' is not a joint of the URDF file");
    refused(write_file("curved.xml", replaced(replaced(kMjcf, " SOLREF", ""), "0 -0.5 0 0 0", "0 -0.5 0.1 0 0")), "",
            "MJCF equality joint 'mimic': its polycoef has non-zero terms of degree 2 to 4");
    refused(write_file("start.urdf", replaced(kUrdf, "LEADER", "lead")), " --position lead=0.4",
            "the start does not satisfy it: joint 'follow' is at 0, the coupling wants -0.2 (give --position follow=-0.2");
}

}  // namespace
}  // namespace mbd::test
