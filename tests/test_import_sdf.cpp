// Issue 37, SDF import (import/src/sdf_reader.cpp) against independent oracles:
// - MuJoCo running the same mechanism written by hand as MJCF: every pose of the MJCF is composed
//   here from the SDF's numbers (rpy_rotation below, not libsdformat), so a wrong frame, axis or
//   inertia resolution on the import side shows as a different motion. Both run 1 s from the
//   same joint velocities; MuJoCo RK4 at h and h / 2 shows its own error; every body frame that
//   both have (not a merged one) is compared, origin and orientation, at every 0.01 s.
// - a closed form for the screw joint (a nut sliding down a vertical screw under gravity);
// - the format known from content, the CLI on a real SDF (../shared/models), `--strict`, and
//   malformed SDF with libsdformat's file:line.
#include "support/mujoco_oracle.hpp"
#include "support/input_files.hpp"
#include "support/test_support.hpp"

#include <mbd/import/import.hpp>
#include <mbd/import/model_format.hpp>
#include <mbd/import/scene_writer.hpp>

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>

namespace mbd::test {
namespace {

namespace fs = std::filesystem;
using import::ImportedScene;

// SDF's <pose> rotation: roll, pitch, yaw about the fixed x, y, z axes, R = Rz(y) Ry(p) Rx(r).
Mat3 rpy_rotation(double r, double p, double y) {
    return (Eigen::AngleAxisd(y, Vec3::UnitZ()) * Eigen::AngleAxisd(p, Vec3::UnitY()) *
            Eigen::AngleAxisd(r, Vec3::UnitX())).toRotationMatrix();
}

std::string text(const Vec3& v) {
    std::ostringstream out;
    out.precision(17);
    out << v.x() << " " << v.y() << " " << v.z();
    return out.str();
}
std::string quat(const Mat3& r) {
    const Vec4 e = euler_parameters_from_rotation(r);
    std::ostringstream out;
    out.precision(17);
    out << e[0] << " " << e[1] << " " << e[2] << " " << e[3];
    return out.str();
}
// MJCF <inertial> of a mass, a mass centre and a full inertia (link axes) turned by `r`.
std::string inertial(double mass, const Vec3& com, const Mat3& inertia, const Mat3& r = Mat3::Identity()) {
    const Mat3 i = r * inertia * r.transpose();
    std::ostringstream out;
    out.precision(17);
    out << "<inertial mass=\"" << mass << "\" pos=\"" << text(com) << "\" fullinertia=\"" << i(0, 0) << " " << i(1, 1)
        << " " << i(2, 2) << " " << i(0, 1) << " " << i(0, 2) << " " << i(1, 2) << "\"/>";
    return out.str();
}
Mat3 inertia(double xx, double yy, double zz, double xy = 0, double xz = 0, double yz = 0) {
    Mat3 i;
    i << xx, xy, xz, xy, yy, yz, xz, yz, zz;
    return i;
}

fs::path write_file(const std::string& name, const std::string& content) {
    return write_scratch_file("import_sdf", name, content);
}

// A six-link arm in a world with tilted gravity and a placed, turned model: a revolute joint to
// the world whose axis is expressed in the model frame, a universal joint whose frame is turned
// 90 degrees about z (its first axis given in the joint frame), a revolute2 with axes 53 degrees
// apart, a ball, a prismatic whose axis is expressed in the parent link, and a fixed tool merged
// into its link; full inertias in turned inertial frames; link poses relative to their parents.
const char* kArmSdf = R"(<?xml version="1.0"?>
<sdf version="1.9">
  <world name="w">
    <gravity>0.4 -0.3 -9.6</gravity>
    <model name="arm6">
      <pose>0.1 -0.2 0.3 0 0 0.4</pose>
      <link name="arm">
        <pose>0 0 2 0.3 0 0</pose>
        <inertial><mass>2</mass><pose>0 0 -0.5 0.2 0.1 0</pose>
          <inertia><ixx>0.30</ixx><iyy>0.25</iyy><izz>0.08</izz><ixy>0.01</ixy><ixz>-0.02</ixz><iyz>0.015</iyz></inertia>
        </inertial>
      </link>
      <joint name="shoulder" type="revolute">
        <parent>world</parent><child>arm</child>
        <axis><xyz expressed_in="__model__">0 1 0</xyz></axis>
      </joint>
      <link name="forearm">
        <pose relative_to="arm">0 0 -1 0 0 0.5</pose>
        <inertial><mass>1.2</mass><pose>0 0 -0.4 0 0 0</pose>
          <inertia><ixx>0.1</ixx><iyy>0.09</iyy><izz>0.02</izz><ixy>0.005</ixy><ixz>0</ixz><iyz>0</iyz></inertia>
        </inertial>
      </link>
      <joint name="elbow" type="universal">
        <pose>0 0 0.05 0 0 1.5707963267948966</pose>
        <parent>arm</parent><child>forearm</child>
        <axis><xyz>1 0 0</xyz></axis>
        <axis2><xyz expressed_in="forearm">1 0 0</xyz></axis2>
      </joint>
      <link name="hand">
        <pose relative_to="forearm">0.1 0 -0.8 0 0.2 0</pose>
        <inertial><mass>0.7</mass><pose>0.05 0 -0.1 0 0 0</pose>
          <inertia><ixx>0.02</ixx><iyy>0.03</iyy><izz>0.025</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia>
        </inertial>
      </link>
      <joint name="wrist" type="ball">
        <pose>0 0 0.1 0 0 0</pose>
        <parent>forearm</parent><child>hand</child>
      </joint>
      <link name="slider">
        <pose relative_to="hand">0 0 -0.3 0 0 0</pose>
        <inertial><mass>0.5</mass>
          <inertia><ixx>0.01</ixx><iyy>0.01</iyy><izz>0.005</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia>
        </inertial>
      </link>
      <joint name="extend" type="prismatic">
        <parent>hand</parent><child>slider</child>
        <axis><xyz expressed_in="hand">0.6 0 -0.8</xyz></axis>
      </joint>
      <link name="tool">
        <pose relative_to="slider">0.1 0 -0.1 0 0 0.3</pose>
        <inertial><mass>0.3</mass>
          <inertia><ixx>0.002</ixx><iyy>0.003</iyy><izz>0.004</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia>
        </inertial>
      </link>
      <joint name="mount" type="fixed"><parent>slider</parent><child>tool</child></joint>
      <link name="finger">
        <pose relative_to="forearm">-0.1 0 -0.5 0 0 0</pose>
        <inertial><mass>0.2</mass><pose>0 0 -0.1 0 0 0</pose>
          <inertia><ixx>0.001</ixx><iyy>0.002</iyy><izz>0.0015</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia>
        </inertial>
      </link>
      <joint name="knuckle" type="revolute2">
        <parent>forearm</parent><child>finger</child>
        <axis><xyz>0 1 0</xyz></axis>
        <axis2><xyz>0.6 0 0.8</xyz></axis2>
      </joint>
    </model>
  </world>
</sdf>
)";

// The same arm as MJCF, each body's pos / quat relative to its parent composed here from the
// SDF's numbers, each joint's axis in its body's frame.
std::string arm_mjcf() {
    const Mat3 arm = rpy_rotation(0.3, 0, 0), forearm = rpy_rotation(0, 0, 0.5), hand = rpy_rotation(0, 0.2, 0);
    const Vec3 shoulder_axis = arm.transpose() * Vec3(0, 1, 0);         // given in the model frame
    const Vec3 elbow_axis = rpy_rotation(0, 0, M_PI / 2) * Vec3(1, 0, 0);  // given in the joint frame
    std::ostringstream x;
    x << "<mujoco model='arm6'><compiler angle='radian'/><option gravity='0.4 -0.3 -9.6'/><worldbody>\n"
      << "<body name='model_frame' pos='0.1 -0.2 0.3' quat='" << quat(rpy_rotation(0, 0, 0.4)) << "'>\n"
      << " <body name='arm' pos='0 0 2' quat='" << quat(arm) << "'>"
      << inertial(2, Vec3(0, 0, -0.5), inertia(0.30, 0.25, 0.08, 0.01, -0.02, 0.015), rpy_rotation(0.2, 0.1, 0))
      << "<joint name='shoulder' type='hinge' axis='" << text(shoulder_axis) << "'/>\n"
      << "  <body name='forearm' pos='0 0 -1' quat='" << quat(forearm) << "'>"
      << inertial(1.2, Vec3(0, 0, -0.4), inertia(0.1, 0.09, 0.02, 0.005))
      << "<joint name='elbow' type='hinge' pos='0 0 0.05' axis='" << text(elbow_axis) << "'/>"
      << "<joint name='elbow_2' type='hinge' pos='0 0 0.05' axis='1 0 0'/>\n"
      << "   <body name='hand' pos='0.1 0 -0.8' quat='" << quat(hand) << "'>"
      << inertial(0.7, Vec3(0.05, 0, -0.1), inertia(0.02, 0.03, 0.025))
      << "<joint name='wrist' type='ball' pos='0 0 0.1'/>\n"
      << "    <body name='slider' pos='0 0 -0.3'>" << inertial(0.5, Vec3::Zero(), inertia(0.01, 0.01, 0.005))
      << "<joint name='extend' type='slide' axis='0.6 0 -0.8'/>\n"
      << "     <body name='tool' pos='0.1 0 -0.1' quat='" << quat(rpy_rotation(0, 0, 0.3)) << "'>"
      << inertial(0.3, Vec3::Zero(), inertia(0.002, 0.003, 0.004)) << "</body>\n"
      << "    </body>\n   </body>\n"
      << "   <body name='finger' pos='-0.1 0 -0.5'>" << inertial(0.2, Vec3(0, 0, -0.1), inertia(0.001, 0.002, 0.0015))
      << "<joint name='knuckle' type='hinge' axis='0 1 0'/><joint name='knuckle_axis2' type='hinge' axis='0.6 0 0.8'/>"
      << "</body>\n  </body>\n </body>\n</body>\n</worldbody></mujoco>\n";
    return x.str();
}

struct Agreement {
    double mujoco_self = 0.0, mbd = 0.0;
    int compared = 0;
};

// MuJoCo at h and h / 2 and mbd (the scene imported with `options`) over 1 s, body frames compared.
Agreement agreement(mjModel* m, const ImportedScene& scene, const std::vector<double>& qvel, double h,
                    const std::vector<double>& qpos = {}) {
    const Model model = load_scene_text(import::scene_yaml(scene), "imported.yaml", shared_registry());
    std::vector<std::vector<double>> xpos[2], xmat[2];
    for (int k = 0; k < 2; ++k)
        mujoco_samples(m, qvel, k ? h / 2 : h, 1.0, 0.01, [&](const mjData* d) {
            xpos[k].emplace_back(d->xpos, d->xpos + 3 * m->nbody);
            xmat[k].emplace_back(d->xmat, d->xmat + 9 * m->nbody);
        }, qpos);
    Agreement a;
    a.mujoco_self = std::max(max_difference(xpos[0], xpos[1]), max_difference(xmat[0], xmat[1]));
    a.mbd = body_frame_difference(m, scene, model, mbd_run(model, 1.0, 0.01), xpos[1], xmat[1], a.compared);
    return a;
}

TEST(ImportSdf, FormatKnownFromContent) {
    const fs::path sdf = write_file("arm6.model", kArmSdf);  // no telling extension
    EXPECT_EQ(import::detect_format(sdf), import::ModelFormat::Sdf);
    EXPECT_EQ(import::detect_format(shared_models() / "sdf_double_pendulum" / "double_pendulum.sdf"),
              import::ModelFormat::Sdf);
}

TEST(ImportSdf, ArmAgreesWithMuJoCoOnTheSameMechanism) {
    const fs::path sdf = write_file("arm6.sdf", kArmSdf);
    MjModelPtr m = compile(write_file("arm6.xml", arm_mjcf()));
    ASSERT_TRUE(m);
    ASSERT_EQ(m->nv, 9);
    // shoulder, elbow (2), wrist (3, body axes), extend, knuckle (2)
    const std::vector<double> qvel{1.0, -0.8, 0.6, 0.5, -0.4, 0.3, 0.2, 1.5, -1.2};
    import::ImportOptions options;
    options.joint_velocities = {{"shoulder", {1.0}}, {"elbow", {-0.8, 0.6}},   {"wrist", {0.5, -0.4, 0.3}},
                                {"extend", {0.2}},   {"knuckle", {1.5}},       {"knuckle_axis2", {-1.2}}};
    const ImportedScene scene = import::import_model(sdf, options);
    EXPECT_EQ(scene.gravity, Vec3(0.4, -0.3, -9.6));
    // arm, forearm, hand, slider (+ tool merged), finger, and the frame between knuckle's hinges
    ASSERT_EQ(scene.bodies.size(), 6u);
    ASSERT_EQ(scene.joints.size(), 6u);
    EXPECT_EQ(scene.joints[1].type, "universal");
    // MuJoCo's RK4 is of order 2 on the ball joint's quaternion (as on a free root, see
    // test_import_oracle.cpp): h and h / 2 differed by 3.45e-8 at h = 2e-4 and by 1.38e-9 at
    // 4e-5 (25 times less for 5 times the step); the error of the h / 2 run is a third of that.
    const Agreement a = agreement(m.get(), scene, qvel, 4e-5);
    std::printf("SDF arm: MuJoCo RK4 h = 4e-5 against 2e-5: %.3g; mbd against MuJoCo: %.3g (%d bodies)\n",
                a.mujoco_self, a.mbd, a.compared);
    EXPECT_EQ(a.compared, 5);  // arm, forearm, hand, slider (merged with tool: its frame moves with it), finger
    EXPECT_LT(a.mujoco_self / 3, 1e-9);  // order 2 (the ball joint's quaternion): the h / 2 run's error
    EXPECT_LT(a.mbd, 1e-6);
}

// The real SDF of ../shared/models/sdf_double_pendulum (libsdformat's own test model, SDF 1.6):
// link poses in the model frame, axes in the child link's frame (no use_parent_model_frame),
// SDF's default inertial (mass 1, unit moments) on both arms, and a base that no joint holds, so
// it is free: the mechanism flies. The MJCF composes the lower link's pose relative to the upper.
std::string double_pendulum_mjcf() {
    const Mat3 upper = rpy_rotation(-1.5708, 0, 0), lower = rpy_rotation(-2, 0, 0);
    const Vec3 upper_at(0, 0, 2.1), lower_at(0.25, 1.0, 2.1);
    const std::string unit = inertial(1, Vec3(0, 0, 0.5), Mat3::Identity());
    std::ostringstream x;
    x << "<mujoco model='double_pendulum_with_base'><option gravity='0 0 -9.8'/><worldbody>\n"
      << "<body name='base'><freejoint name='base_free'/>" << inertial(100, Vec3::Zero(), Mat3::Identity()) << "\n"
      << " <body name='upper_link' pos='" << text(upper_at) << "' quat='" << quat(upper) << "'>" << unit
      << "<joint name='upper_joint' type='hinge' axis='1 0 0'/>\n"
      << "  <body name='lower_link' pos='" << text(upper.transpose() * (lower_at - upper_at)) << "' quat='"
      << quat(upper.transpose() * lower) << "'>" << unit << "<joint name='lower_joint' type='hinge' axis='1 0 0'/>"
      << "</body>\n </body>\n</body>\n</worldbody></mujoco>\n";
    return x.str();
}

TEST(ImportSdf, SharedDoublePendulumAgreesWithMuJoCo) {
    const fs::path sdf = shared_models() / "sdf_double_pendulum" / "double_pendulum.sdf";
    MjModelPtr m = compile(write_file("double_pendulum.xml", double_pendulum_mjcf()));
    ASSERT_TRUE(m);
    const std::vector<double> qvel{0.1, 0.0, 0.2, 0.05, -0.1, 0.02, 1.5, -2.0};
    import::ImportOptions options;
    options.joint_velocities = {{"base_free", {0.1, 0.0, 0.2, 0.05, -0.1, 0.02}}, {"upper_joint", {1.5}}, {"lower_joint", {-2.0}}};
    const ImportedScene scene = import::import_model(sdf, options);
    EXPECT_EQ(scene.gravity, Vec3(0, 0, -9.8));  // SDF's default: the file is a model without a world
    ASSERT_EQ(scene.bodies.size(), 3u);
    ASSERT_EQ(scene.joints.size(), 2u);
    EXPECT_EQ(scene.bodies[1].mass, 1.0);  // SDF's default inertial
    // order 2 on the free base's quaternion, as for the arm's ball joint
    const Agreement a = agreement(m.get(), scene, qvel, 4e-5);
    std::printf("SDF double pendulum: MuJoCo RK4 h = 4e-5 against 2e-5: %.3g; mbd against MuJoCo: %.3g (%d bodies)\n",
                a.mujoco_self, a.mbd, a.compared);
    EXPECT_EQ(a.compared, 3);
    EXPECT_LT(a.mujoco_self / 3, 1e-9);
    EXPECT_LT(a.mbd, 1e-6);
}

// Initial joint positions (--position): the double pendulum started with its joints at 0.4 and
// -0.7 rad from the file's configuration, against MuJoCo started at qpos0 + the same angles
// (every body frame compared from t = 0, so a subtree turned about the wrong point or axis shows).
TEST(ImportSdf, InitialJointPositionsAgreeWithMuJoCo) {
    const fs::path sdf = shared_models() / "sdf_double_pendulum" / "double_pendulum.sdf";
    MjModelPtr m = compile(write_file("double_pendulum.xml", double_pendulum_mjcf()));
    ASSERT_TRUE(m);
    std::vector<double> qpos(m->qpos0, m->qpos0 + m->nq);
    qpos[7] += 0.4;   // upper_joint, after the free base's 7
    qpos[8] -= 0.7;   // lower_joint
    const std::vector<double> qvel{0, 0, 0, 0, 0, 0, 1.0, 0.5};
    import::ImportOptions options;
    options.joint_positions = {{"upper_joint", 0.4}, {"lower_joint", -0.7}};
    options.joint_velocities = {{"upper_joint", {1.0}}, {"lower_joint", {0.5}}};
    const ImportedScene scene = import::import_model(sdf, options);
    const Agreement a = agreement(m.get(), scene, qvel, 4e-5, qpos);
    std::printf("SDF double pendulum from moved joints: MuJoCo h against h / 2: %.3g; mbd against MuJoCo: %.3g\n",
                a.mujoco_self, a.mbd);
    EXPECT_EQ(a.compared, 3);
    EXPECT_LT(a.mujoco_self / 3, 1e-9);
    EXPECT_LT(a.mbd, 1e-6);
    options.joint_positions = {{"no_such_joint", 0.1}};
    EXPECT_THROW(import::import_model(sdf, options), InputError);
}

// A nut of mass m and axial moment I on a vertical screw (the world's), released at rest: with
// travel z = k theta, k = pitch / (2 pi), Lagrange gives theta'' = -m g k / (m k^2 + I). SDF's
// thread_pitch 20 rad/m in Gazebo's sign convention is k = -1/20 m/rad (docs/import.md), so the
// falling nut turns positively about +z.
TEST(ImportSdf, ScrewJointNutFollowsTheClosedForm) {
    const fs::path sdf = write_file("screw.sdf", R"(<?xml version="1.0"?>
<sdf version="1.9"><model name="lead_screw">
  <link name="nut"><pose>0 0 1 0 0 0</pose>
    <inertial><mass>2</mass><inertia><ixx>0.05</ixx><iyy>0.05</iyy><izz>0.08</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia></inertial>
  </link>
  <joint name="lead" type="screw"><parent>world</parent><child>nut</child>
    <thread_pitch>20</thread_pitch><axis><xyz>0 0 1</xyz></axis></joint>
</model></sdf>
)");
    const ImportedScene scene = import::import_model(sdf);
    ASSERT_EQ(scene.joints.size(), 1u);
    EXPECT_EQ(scene.joints[0].type, "screw");
    const Model model = load_scene_text(import::scene_yaml(scene), "screw.yaml", shared_registry());
    const std::vector<Eigen::VectorXd> q = mbd_run(model, 1.0, 0.5);
    ASSERT_EQ(q.size(), 3u);
    const double mass = 2, moment = 0.08, g = 9.8, k = -1.0 / 20;
    const double turn = -mass * g * k / (mass * k * k + moment);  // rad/s^2
    const Vec4 e = q.back().segment<4>(3);
    EXPECT_NEAR(q.back()[2], 1.0 + 0.5 * k * turn, 1e-9);  // z(1 s)
    EXPECT_NEAR(wrap_angle(2.0 * std::atan2(e[3], e[0]) - 0.5 * turn), 0.0, 1e-9);
    EXPECT_NEAR(q.back()[0], 0.0, 1e-12);
}

// The CLI on the real SDF: one warning naming what is left out (geometry), `--strict` refuses
// it (exit 2, nothing written), and malformed SDF is refused with libsdformat's file:line.
TEST(ImportSdf, CommandLineWarnsRefusesStrictAndReportsBadXml) {
    const fs::path sdf = shared_models() / "sdf_double_pendulum" / "double_pendulum.sdf";
    const CommandResult check = run_mbd("check " + sdf.string());
    EXPECT_EQ(check.exit_code, 0) << check.err;
    EXPECT_EQ(check.err.find("mbd: warning:"), check.err.rfind("mbd: warning:")) << check.err;
    EXPECT_NE(check.err.find("geometry (base, upper_link, lower_link)"), std::string::npos) << check.err;
    const fs::path out = scratch("import_sdf_cli") / "pendulum.yaml";
    const CommandResult strict = run_mbd("import " + sdf.string() + " --strict -o " + out.string());
    EXPECT_EQ(strict.exit_code, 2) << strict.err;
    EXPECT_NE(strict.err.find("--strict"), std::string::npos) << strict.err;
    EXPECT_FALSE(fs::exists(out));
    const CommandResult imported = run_mbd("import " + sdf.string() + " -o " + out.string());
    EXPECT_EQ(imported.exit_code, 0) << imported.err;
    EXPECT_NE(read_text(out).find("name: upper_joint, type: revolute"), std::string::npos);
    EXPECT_NE(read_text(out).find("double_pendulum.sdf:192: SDF joint 'upper_joint'"), std::string::npos);

    const fs::path bad = write_file("bad.sdf", "<?xml version=\"1.0\"?>\n<sdf version=\"1.9\">\n<model name=\"m\">\n"
                                               "  <link name=\"a\">\n</model>\n</sdf>\n");
    const CommandResult refused = run_mbd("import " + bad.string() + " -o " + (bad.string() + ".yaml"));
    EXPECT_EQ(refused.exit_code, 2) << refused.err;
    EXPECT_NE(refused.err.find("bad.sdf:5: malformed XML"), std::string::npos) << refused.err;  // </model> for </link>
    EXPECT_FALSE(fs::exists(bad.string() + ".yaml"));
    // well-formed, but a joint names a link the model does not have: libsdformat's message
    const fs::path missing = write_file("missing.sdf", "<?xml version=\"1.0\"?>\n<sdf version=\"1.9\">\n<model name=\"m\">\n"
                                                       "  <link name=\"a\"/>\n  <joint name=\"hinge\" type=\"revolute\">\n"
                                                       "    <parent>world</parent><child>b</child><axis><xyz>0 0 1</xyz></axis>\n"
                                                       "  </joint>\n</model>\n</sdf>\n");
    const CommandResult unknown = run_mbd("import " + missing.string() + " -o " + (missing.string() + ".yaml"));
    EXPECT_EQ(unknown.exit_code, 2) << unknown.err;
    EXPECT_NE(unknown.err.find("missing.sdf:"), std::string::npos) << unknown.err;
    EXPECT_NE(unknown.err.find("hinge"), std::string::npos) << unknown.err;
    EXPECT_FALSE(fs::exists(missing.string() + ".yaml"));
    std::printf("SDF errors:\n%s%s", refused.err.c_str(), unknown.err.c_str());
}

}  // namespace
}  // namespace mbd::test
