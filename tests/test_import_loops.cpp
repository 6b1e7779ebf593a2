// Issue 37, MJCF equality constraints as mbd joints (import/src/mjcf_reader.cpp, read_equalities),
// so that closed loops import:
// - a four-bar closed by `connect` against the same four-bar written by hand as an mbd scene
//   with four revolute joints (MuJoCo's equality constraints are soft, so MuJoCo is not the
//   oracle here; the hand-written scene shares no code with the import);
// - a body held by `weld` against MuJoCo running the same bodies nested (a child body without a
//   joint, which MuJoCo treats exactly);
// - what is not mapped (a `joint` coupling) stays in the one warning; a weld whose relpose is not
//   the pose at qpos0 is refused naming it.
#include "support/mujoco_oracle.hpp"
#include "support/input_files.hpp"
#include "support/test_support.hpp"

#include <mbd/import/import.hpp>
#include <mbd/import/scene_writer.hpp>

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>

namespace mbd::test {
namespace {

namespace fs = std::filesystem;
using import::ImportedScene;

fs::path write_file(const std::string& name, const std::string& content) {
    return write_scratch_file("import_loops", name, content);
}

std::string text(const Vec3& v) {
    std::ostringstream out;
    out.precision(17);
    out << "[" << v.x() << ", " << v.y() << ", " << v.z() << "]";
    return out.str();
}

// A Grashof crank-rocker in the x-z plane, all axes along y: crank O(0,0,0)-A(0.2,0,0), coupler
// A-B(0.55,0,0.4), rocker B-C(0.6,0,0), ground O-C; s + l = 0.2 + 0.6 < p + q = 0.532 + 0.403.
const Vec3 kO(0, 0, 0), kA(0.2, 0, 0), kB(0.55, 0, 0.4), kC(0.6, 0, 0);
struct Link {
    const char* name;
    double mass;
    Vec3 from, to, moments;  // principal moments about the mass centre, x y z
};
const Link kLinks[3] = {{"crank", 1.0, kO, kA, Vec3(0.0005, 0.004, 0.004)},
                        {"coupler", 1.5, kA, kB, Vec3(0.012, 0.015, 0.005)},
                        {"rocker", 0.8, kC, kB, Vec3(0.007, 0.008, 0.002)}};
// Absolute rates about +y: the crank at w1; the loop's velocity closure (v_B by the crank and
// coupler = v_B by the rocker, v = w y x r) gives coupler and rocker both at -w1 / 2.
const double kCrankRate = 3.0, kRates[3] = {3.0, -1.5, -1.5};

Vec3 centre(const Link& l) { return 0.5 * (l.from + l.to); }

// The four-bar written by hand as an mbd scene: four revolute joints.
std::string hand_written_scene() {
    std::ostringstream y;
    y << "name: four-bar-by-hand\ndimension: spatial\ngravity: [0, 0, -9.81]\nbodies:\n";
    for (int k = 0; k < 3; ++k) {
        const Link& l = kLinks[k];
        const Vec3 w = kRates[k] * Vec3::UnitY();
        // the coupler's pivot A moves with the crank; the crank's and rocker's pivots are fixed
        const Vec3 pivot_velocity = k == 1 ? Vec3(kRates[0] * Vec3::UnitY().cross(kA - kO)) : Vec3::Zero();
        y << "  - {name: " << l.name << ", mass: " << l.mass << ", inertia: " << text(l.moments)
          << ", position: " << text(centre(l)) << ", velocity: " << text(pivot_velocity + w.cross(centre(l) - l.from))
          << ", angular_velocity: " << text(w) << "}\n";
    }
    y << "joints:\n"
      << "  - {name: O, type: revolute, bodies: [ground, crank], point: " << text(kO) << ", axis: [0, 1, 0]}\n"
      << "  - {name: A, type: revolute, bodies: [crank, coupler], point: " << text(kA) << ", axis: [0, 1, 0]}\n"
      << "  - {name: C, type: revolute, bodies: [ground, rocker], point: " << text(kC) << ", axis: [0, 1, 0]}\n"
      << "  - {name: B, type: revolute, bodies: [coupler, rocker], point: " << text(kB) << ", axis: [0, 1, 0]}\n";
    return y.str();
}

// The same four-bar as MJCF: crank and coupler a chain, the rocker its own chain, the loop closed
// at B by `connect` (anchor in the coupler's frame, whose origin is A).
std::string connect_mjcf() {
    auto body = [](const Link& l, const Vec3& origin) {  // origin: world (the crank's is O = 0, so also relative)
        std::ostringstream b;
        b.precision(17);
        const Vec3 c = centre(l) - origin;
        b << "<body name='" << l.name << "' pos='" << origin.x() << " " << origin.y() << " " << origin.z() << "'>"
          << "<joint name='" << l.name << "_pin' type='hinge' axis='0 1 0'/><inertial mass='" << l.mass << "' pos='"
          << c.x() << " " << c.y() << " " << c.z() << "' diaginertia='" << l.moments.x() << " " << l.moments.y() << " "
          << l.moments.z() << "'/>";
        return b.str();
    };
    const Vec3 anchor = kB - kA;
    std::ostringstream x;
    x.precision(17);
    x << "<mujoco model='four-bar'><worldbody>\n" << body(kLinks[0], kO) << "\n  " << body(kLinks[1], kA - kO)
      << "</body></body>\n" << body(kLinks[2], kC) << "</body>\n</worldbody>\n<equality><connect name='loop' "
      << "body1='coupler' body2='rocker' anchor='" << anchor.x() << " " << anchor.y() << " " << anchor.z()
      << "'/></equality></mujoco>\n";
    return x.str();
}

// The largest difference of the bodies' positions and orientations between `imported` (run by
// the embedding formulation) and the hand-written scene run by the augmented formulation (the
// constraints' multipliers solved with the accelerations), so that agreement does not rest on
// one solver's path, every 0.01 s over 1 s. Also checks that the mechanism moves.
double difference_from_hand_written(const Model& imported) {
    const Model by_hand = load_scene_text(hand_written_scene(), "four_bar_by_hand.yaml", shared_registry());
    const std::vector<Eigen::VectorXd> a = mbd_run(imported, 1.0, 0.01), b = mbd_run(by_hand, 1.0, 0.01, "augmented");
    EXPECT_EQ(a.size(), b.size());
    double worst = 0.0, rocker_swing = 0.0;
    for (const Link& l : kLinks) {
        const int i = imported.body_index(l.name), j = by_hand.body_index(l.name);
        for (size_t s = 0; s < a.size() && s < b.size(); ++s) {
            worst = std::max(worst, (a[s].segment<3>(7 * i) - b[s].segment<3>(7 * j)).cwiseAbs().maxCoeff());
            const Vec4 p = a[s].segment<4>(7 * i + 3);
            const Vec4 e = quaternion_product(Vec4(p[0], -p[1], -p[2], -p[3]), b[s].segment<4>(7 * j + 3));
            worst = std::max(worst, 2.0 * std::asin(std::min(1.0, e.tail<3>().norm())));
            if (std::string(l.name) == "rocker")
                rocker_swing = std::max(rocker_swing, (a[s].segment<3>(7 * i) - a[0].segment<3>(7 * i)).norm());
        }
    }
    EXPECT_GT(rocker_swing, 0.05) << "the rocker's centre moves (0.175 m)";
    return worst;
}

// An imported four-bar closed at B by a joint of `type`, nothing left unmapped, moves as the
// hand-written scene to 1e-8 over 1 s.
void expect_closed_four_bar(const ImportedScene& scene, const std::string& type, const std::string& label) {
    ASSERT_EQ(scene.joints.size(), 4u);
    EXPECT_EQ(scene.joints.back().type, type);
    EXPECT_LT((scene.joints.back().point - kB).norm(), 1e-15);
    EXPECT_EQ(import::unmapped_summary(scene.unmapped), "");
    const Model imported = load_scene_text(import::scene_yaml(scene), "four_bar.yaml", shared_registry());
    const double worst = difference_from_hand_written(imported);
    std::printf("%s (embedding) against the hand-written scene (augmented): %.3g over 1 s\n", label.c_str(), worst);
    EXPECT_LT(worst, 1e-8);
}

TEST(ImportLoops, FourBarClosedByConnectMatchesTheHandWrittenScene) {
    const fs::path mjcf = write_file("four_bar.xml", connect_mjcf());
    import::ImportOptions options;  // MuJoCo's joint rates: relative to the parent
    options.joint_velocities = {{"crank_pin", {kCrankRate}}, {"coupler_pin", {kRates[1] - kRates[0]}}, {"rocker_pin", {kRates[2]}}};
    const ImportedScene scene = import::import_model(mjcf, options);
    expect_closed_four_bar(scene, "spherical", "four-bar by connect");
}

// The same four-bar as SDF: the rocker is the child of two revolute joints, C to the world and
// B to the coupler; libsdformat's second one (B, with its pose relative to the rocker) closes
// the loop as a revolute joint.
TEST(ImportLoops, SdfFourBarClosedByASecondJointMatchesTheHandWrittenScene) {
    std::ostringstream x;
    x.precision(17);
    x << "<?xml version='1.0'?>\n<sdf version='1.9'><world name='w'><gravity>0 0 -9.81</gravity><model name='four_bar'>\n";
    for (const Link& l : kLinks) {
        const Vec3 c = centre(l) - l.from;
        x << "<link name='" << l.name << "'><pose>" << l.from.x() << " " << l.from.y() << " " << l.from.z() << " 0 0 0</pose>"
          << "<inertial><mass>" << l.mass << "</mass><pose>" << c.x() << " " << c.y() << " " << c.z() << " 0 0 0</pose><inertia><ixx>"
          << l.moments.x() << "</ixx><iyy>" << l.moments.y() << "</iyy><izz>" << l.moments.z()
          << "</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia></inertial></link>\n";
    }
    auto joint = [&](const char* name, const char* parent, const char* child, const Vec3& at) {
        x << "<joint name='" << name << "' type='revolute'><pose>" << at.x() << " " << at.y() << " " << at.z()
          << " 0 0 0</pose><parent>" << parent << "</parent><child>" << child << "</child><axis><xyz>0 1 0</xyz></axis></joint>\n";
    };
    joint("O", "world", "crank", Vec3::Zero());  // joint poses relative to the child link's frame
    joint("A", "crank", "coupler", Vec3::Zero());
    joint("C", "world", "rocker", Vec3::Zero());
    joint("B", "coupler", "rocker", kB - kC);
    x << "</model></world></sdf>\n";
    import::ImportOptions options;
    options.joint_velocities = {{"O", {kCrankRate}}, {"A", {kRates[1] - kRates[0]}}, {"C", {kRates[2]}}};
    const ImportedScene scene = import::import_model(write_file("four_bar.sdf", x.str()), options);
    expect_closed_four_bar(scene, "revolute", "SDF four-bar");
    if (!scene.joints.empty()) EXPECT_EQ(scene.joints.back().name, "B");
}

// A pendulum arm with a block held by `weld` (the block has its own free joint) against MuJoCo
// running the block nested in the arm without a joint.
TEST(ImportLoops, WeldHoldsLikeANestedBodyInMuJoCo) {
    const std::string arm = "<body name='arm' pos='0 0 1'><joint name='pin' type='hinge' axis='0.3 1 0.2'/>"
                            "<inertial mass='1' pos='0.25 0 0' diaginertia='0.001 0.02 0.02'/>";
    const std::string block = "<body name='block' pos='0.5 0.1 -0.05' euler='0.2 0.4 -0.3'>"
                              "<inertial mass='0.4' pos='0.02 0 0.01' diaginertia='0.001 0.002 0.0025'/>";
    const fs::path welded = write_file("welded.xml", "<mujoco model='welded'><worldbody>" + arm + "</body><body name='block' "
                                       "pos='0.5 0.1 0.95' euler='0.2 0.4 -0.3'><freejoint name='block_free'/>"
                                       "<inertial mass='0.4' pos='0.02 0 0.01' diaginertia='0.001 0.002 0.0025'/></body>"
                                       "</worldbody><equality><weld name='glue' body1='arm' body2='block'/></equality></mujoco>");
    const fs::path nested = write_file("nested.xml", "<mujoco model='nested'><worldbody>" + arm + block +
                                       "</body></body></worldbody></mujoco>");
    MjModelPtr m = compile(nested);
    ASSERT_TRUE(m);
    import::ImportOptions options;
    options.joint_velocities = {{"pin", {2.0}}};
    // the free block starts at rest and the weld needs its velocity to be the arm's: give it
    ImportedScene scene = import::import_model(welded, options);
    ASSERT_EQ(scene.joints.size(), 2u);
    EXPECT_EQ(scene.joints[1].type, "fixed");
    const import::SceneBody& arm_body = scene.bodies[0];
    import::SceneBody& block_body = scene.bodies[1];
    block_body.angular_velocity = arm_body.angular_velocity;
    block_body.velocity = arm_body.angular_velocity.cross(block_body.position - scene.joints[0].point);
    const Model model = load_scene_text(import::scene_yaml(scene), "welded.yaml", shared_registry());
    const MujocoFrames mujoco = mujoco_frames(m.get(), {2.0}, 1e-4, 1.0, 0.01);
    int compared = 0;
    const double worst = body_frame_difference(m.get(), scene, model, mbd_run(model, 1.0, 0.01), mujoco.xpos, mujoco.xmat, compared);
    std::printf("weld against MuJoCo's nested body: %.3g over 1 s\n", worst);
    EXPECT_EQ(compared, 2);
    EXPECT_LT(worst, 1e-6);
}

TEST(ImportLoops, UnmappedCouplingIsListedAndAWrongRelposeRefused) {
    const std::string bodies = "<worldbody><body name='a'><joint name='ja' type='hinge' axis='0 1 0'/>"
                               "<inertial mass='1' pos='0.1 0 0' diaginertia='0.01 0.01 0.01'/></body>"
                               "<body name='b' pos='1 0 0'><joint name='jb' type='hinge' axis='0 1 0'/>"
                               "<inertial mass='1' pos='0.1 0 0' diaginertia='0.01 0.01 0.01'/></body></worldbody>";
    const fs::path coupled = write_file("coupled.xml", "<mujoco>" + bodies +
                                        "<equality><joint name='gear' joint1='ja' joint2='jb' polycoef='0 2 0 0 0'/>"
                                        "<joint name='hold' joint1='jb'/></equality></mujoco>");
    // a joint coupling is imported (tests/test_import_couplings.cpp); a joint held alone (no joint2) is listed
    const ImportedScene scene = import::import_model(coupled);
    EXPECT_EQ(scene.couplings.size(), 1u);
    EXPECT_NE(import::unmapped_summary(scene.unmapped).find("1 equality constraints (hold)"), std::string::npos)
        << import::unmapped_summary(scene.unmapped);
    const fs::path wrong = write_file("wrong.xml", "<mujoco>" + bodies +
                                      "<equality><weld name='glue' body1='a' body2='b' relpose='0 0 0 1 0 0 0'/></equality></mujoco>");
    const CommandResult r = run_mbd("import " + wrong.string() + " -o " + (wrong.string() + ".yaml"));
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("MJCF weld 'glue': its relpose"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(wrong.string() + ".yaml"));
}

}  // namespace
}  // namespace mbd::test
