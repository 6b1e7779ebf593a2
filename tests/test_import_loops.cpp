// Issue 37, MJCF equality constraints as mbd joints (import/src/mjcf_reader.cpp, read_equalities),
// so that closed loops import:
// - a four-bar closed by `connect` (also with every body frame turned) against the same four-bar
//   written by hand as an mbd scene with four revolute joints (the hand-written scene shares no
//   code with the import);
// - the turned four-bar and menagerie's cassie (four `connect` loops) against MuJoCo's runs of the
//   same files with their (soft) constraints made stiff: MuJoCo converges to mbd's exact joints
//   at order 2 in the constraints' time constant, its extrapolation agrees to 1e-6;
// - a body held by `weld` against MuJoCo running the same bodies nested (a child body without a
//   joint, which MuJoCo treats exactly);
// - what is not mapped (a `joint` coupling) stays in the one warning; a weld whose relpose is not
//   the pose at qpos0 is refused naming it.
#include "support/mujoco_oracle.hpp"
#include "support/input_files.hpp"
#include "support/test_support.hpp"

#include <mbd/import/import.hpp>
#include <mbd/import/mjcf_reader.hpp>
#include <mbd/import/scene_writer.hpp>

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <set>
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

// A Grashof crank-rocker in the plane y = y0, all axes along y: crank O(0,y0,0)-A(0.2,y0,0), coupler
// A-B(0.55,y0,0.4), rocker B-C(0.6,y0,0), ground O-C; s + l = 0.2 + 0.6 < p + q = 0.532 + 0.403.
// y0 = 0.11566, the plane of cassie's plantar loops: off y = 0, a turned frame leaves rounding
// noise in the loop's dependent y row (test_loop_closure.cpp, PlanarLoopClosedByABall...).
constexpr double kY0 = 0.11566;
const Vec3 kO(0, kY0, 0), kA(0.2, kY0, 0), kB(0.55, kY0, 0.4), kC(0.6, kY0, 0);
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
// at B by `connect` (its anchor in the coupler's frame, whose origin is A). `axes`: each body
// frame's axes in world (crank, coupler, rocker); every position, hinge axis and the anchor is
// written in its body's frame, and each inertial frame turned back to world axes, so that any
// axes give the same mechanism.
std::string connect_mjcf(const Mat3 (&axes)[3] = {Mat3::Identity(), Mat3::Identity(), Mat3::Identity()}) {
    auto number = [](double x) {
        std::ostringstream w;
        w.precision(17);
        w << x;
        return w.str();
    };
    auto words = [&](const auto& v) {
        std::string w;
        for (int k = 0; k < v.size(); ++k) w += (k ? " " : "") + number(v[k]);
        return w;
    };
    auto quat = [&](const Mat3& r) { return words(euler_parameters_from_rotation(r)); };  // MuJoCo's w x y z
    // link k: its frame at `pos`, turned by `turn`, both in its parent's frame
    auto body = [&](int k, const Vec3& pos, const Mat3& turn) {
        const Link& l = kLinks[k];
        const Mat3& r = axes[k];
        return "<body name='" + std::string(l.name) + "' pos='" + words(pos) + "' quat='" + quat(turn) + "'><joint name='" +
               l.name + "_pin' type='hinge' axis='" + words(Vec3(r.transpose() * Vec3::UnitY())) + "'/><inertial mass='" + number(l.mass) + "' pos='" +
               words(Vec3(r.transpose() * (centre(l) - l.from))) + "' quat='" + quat(r.transpose()) + "' diaginertia='" +
               words(l.moments) + "'/>";
    };
    return "<mujoco model='four-bar'><worldbody>\n" + body(0, kO, axes[0]) + "\n  " +
           body(1, axes[0].transpose() * (kA - kO), axes[0].transpose() * axes[1]) + "</body></body>\n" +
           body(2, kC, axes[2]) + "</body>\n</worldbody>\n<equality><connect name='loop' body1='coupler' body2='rocker' "
           "anchor='" + words(Vec3(axes[1].transpose() * (kB - kA))) + "'/></equality></mujoco>\n";
}

// The largest difference of the bodies' mass centres and turns between `imported` (run by
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
            // each body's turn since t = 0 (world axes): independent of the body axes each scene chose
            const Mat3 turn_a = rotation_from_euler_parameters(a[s].segment<4>(7 * i + 3)) *
                                rotation_from_euler_parameters(a[0].segment<4>(7 * i + 3)).transpose();
            const Mat3 turn_b = rotation_from_euler_parameters(b[s].segment<4>(7 * j + 3)) *
                                rotation_from_euler_parameters(b[0].segment<4>(7 * j + 3)).transpose();
            const Vec4 e = euler_parameters_from_rotation(turn_a.transpose() * turn_b);
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
    EXPECT_LT((scene.joints.back().point - kB).norm(), 1e-14);
    EXPECT_EQ(import::unmapped_summary(scene.unmapped), "");
    const Model imported = load_scene_text(import::scene_yaml(scene), "four_bar.yaml", shared_registry());
    const double worst = difference_from_hand_written(imported);
    std::printf("%s (embedding) against the hand-written scene (augmented): %.3g over 1 s\n", label.c_str(), worst);
    EXPECT_LT(worst, 1e-8);
}

// MuJoCo's joint rates of the four-bar (relative to the parent, about +y), as the import's options
// and as MuJoCo's qvel.
import::ImportOptions four_bar_rates() {
    import::ImportOptions options;
    options.joint_velocities = {{"crank_pin", {kCrankRate}}, {"coupler_pin", {kRates[1] - kRates[0]}}, {"rocker_pin", {kRates[2]}}};
    return options;
}
const std::vector<double> kFourBarQvel = {kCrankRate, kRates[1] - kRates[0], kRates[2]};

TEST(ImportLoops, FourBarClosedByConnectMatchesTheHandWrittenScene) {
    const fs::path mjcf = write_file("four_bar.xml", connect_mjcf());
    expect_closed_four_bar(import::import_model(mjcf, four_bar_rates()), "spherical", "four-bar by connect");
}

// Body frames turned every way (none along the hinges), so that the connect's anchor, the
// hinge axes and the inertial frames are all written in turned frames, and MuJoCo's point on the
// rocker is where the coupler's anchor lies at qpos0 (its compiler's rule, mj_setConst).
const Mat3 kTurnedAxes[3] = {Eigen::AngleAxisd(0.7, Vec3(0.3, 0.5, 0.8).normalized()).toRotationMatrix(),
                             Eigen::AngleAxisd(1.9, Vec3(-0.6, 0.2, 0.4).normalized()).toRotationMatrix(),
                             Eigen::AngleAxisd(2.6, Vec3(0.1, -0.9, 0.3).normalized()).toRotationMatrix()};

TEST(ImportLoops, FourBarInTurnedFramesClosedByConnectMatchesTheHandWrittenScene) {
    const fs::path mjcf = write_file("four_bar_turned.xml", connect_mjcf(kTurnedAxes));
    expect_closed_four_bar(import::import_model(mjcf, four_bar_rates()), "spherical", "four-bar in turned frames by connect");
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

namespace mbd::test {
namespace {

// MuJoCo's equality constraints are soft: a connect pulls its two points together like a
// spring-damper of time constant solref[0] (damping ratio solref[1]), so MuJoCo's run of a file
// with loops is not the exact mechanism. Made stiff through the compiled model (time constant tc,
// ratio 1, impedance 0.9999, mjDSBL_REFSAFE so that tc may be below 2 h), MuJoCo's motion
// converges to the exact loops' at order 2 in tc (measured: the gap to mbd falls by 4.0 per
// halving of tc), so MuJoCo's Richardson extrapolation in tc is the oracle of mbd's exact joints.
void stiffen_connects(mjModel* m, double tc) {
    m->opt.disableflags |= mjDSBL_REFSAFE;
    for (int e = 0; e < m->neq; ++e) {
        m->eq_solref[mjNREF * e] = tc, m->eq_solref[mjNREF * e + 1] = 1.0;
        m->eq_solimp[mjNIMP * e] = m->eq_solimp[mjNIMP * e + 1] = 0.9999;
    }
}

struct StiffenedAgreement {
    size_t joints = 0;          // of the imported scene
    double soft = 0.0;          // MuJoCo with the file's constraints against MuJoCo at the stiffest, in qpos
    double mbd[3] = {0, 0, 0};  // mbd against MuJoCo at tc, tc / 2, tc / 4 (trajectory_difference)
    double extrapolated = 0.0;  // mbd against (4 x(tc / 4) - x(tc / 2)) / 3
    double mujoco_self = 0.0;   // MuJoCo at tc / 4: step h against h / 2, in qpos
};

// The MJCF `file` compiled with contacts, limits, actuators and passive forces off (conservative_tree)
// and its equality constraints on, imported with them as exact joints (the embedding
// formulation's closure path), started with qvel (`options` the same for the import) and run to
// t_end against MuJoCo: soft at step 10 h (its time constant allows it), stiffened at step h.
StiffenedAgreement stiffened_agreement(const fs::path& file, const std::vector<double>& qvel,
                                       const import::ImportOptions& options, double t_end, double h, double tc) {
    MjModelPtr m = compile(file);
    if (!m) return {};
    conservative_tree(m.get());
    m->opt.disableflags &= ~mjDSBL_EQUALITY;
    import::SourceTree tree = import::read_mjcf_model(m.get(), file.string());
    import::apply_joint_velocities(tree, options);
    const ImportedScene scene = import::build_scene(tree);
    const Model model = load_scene_text(import::scene_yaml(scene), file.filename().string() + ".yaml", shared_registry());
    const std::vector<Eigen::VectorXd> q = mbd_run(model, t_end, 0.01);
    StiffenedAgreement out;
    out.joints = scene.joints.size();
    const auto soft = mujoco_run(m.get(), qvel, 10 * h, t_end, 0.01);
    std::vector<std::vector<std::vector<double>>> stiff;
    for (int k = 0; k < 3; ++k) {
        stiffen_connects(m.get(), tc / (1 << k));
        stiff.push_back(mujoco_run(m.get(), qvel, h, t_end, 0.01));
        out.mbd[k] = trajectory_difference(m.get(), scene, model, q, stiff.back());
    }
    out.soft = max_difference(soft, stiff[2]);
    out.mujoco_self = max_difference(stiff[2], mujoco_run(m.get(), qvel, h / 2, t_end, 0.01));
    auto extrapolated = stiff[2];
    for (size_t s = 0; s < extrapolated.size(); ++s)
        for (size_t k = 0; k < extrapolated[s].size(); ++k) extrapolated[s][k] = (4 * stiff[2][s][k] - stiff[1][s][k]) / 3;
    out.extrapolated = trajectory_difference(m.get(), scene, model, q, extrapolated);
    std::printf("%s over %g s: MuJoCo soft (the file's constraints) against stiff %.3g; mbd against MuJoCo stiffened "
                "at tc = %g, %g, %g: %.3g, %.3g, %.3g (ratios %.2f, %.2f); extrapolated %.3g; MuJoCo h = %g against "
                "h / 2 %.3g\n",
                file.filename().c_str(), t_end, out.soft, tc, tc / 2, tc / 4, out.mbd[0], out.mbd[1], out.mbd[2],
                out.mbd[0] / out.mbd[1], out.mbd[1] / out.mbd[2], out.extrapolated, h, out.mujoco_self);
    return out;
}

// Order 2 in tc and the extrapolation to `bound`, MuJoCo's own error below 1e-8.
void expect_converges_to_mbd(const StiffenedAgreement& a, double bound) {
    for (int k = 0; k < 2; ++k) {
        EXPECT_GT(a.mbd[k] / a.mbd[k + 1], 3.5);
        EXPECT_LT(a.mbd[k] / a.mbd[k + 1], 4.5);
    }
    EXPECT_LT(a.extrapolated, bound);
    EXPECT_LT(a.extrapolated, a.mbd[2] / 10);
    EXPECT_LT(a.mujoco_self, 1e-8);
}

// The four-bar in turned frames against MuJoCo's run of the same file, over 1 s.
TEST(ImportLoops, FourBarByConnectAgreesWithMuJoCoStiffened) {
    const fs::path mjcf = write_file("four_bar_turned_mujoco.xml", connect_mjcf(kTurnedAxes));
    const StiffenedAgreement a = stiffened_agreement(mjcf, kFourBarQvel, four_bar_rates(), 1.0, 5e-5, 4e-4);
    EXPECT_EQ(a.joints, 4u);
    EXPECT_GT(a.soft, 1e-3);  // the file's soft connect moves the four-bar visibly otherwise
    expect_converges_to_mbd(a, 1e-6);
}

// Agility's cassie from mujoco_menagerie (../shared/models/cassie): a free pelvis, 20 hinges and
// 2 ball joints (the achilles rods), its four `connect` constraints closing the achilles and
// plantar loops as four exact ball joints. Started at qpos0 (where MuJoCo's compiler closes the
// loops) with the free pelvis and the six hip joints moving at the documented rates
// (initial_velocities) and every joint inside a loop at rest, so that the start satisfies the
// loops at position and velocity level. Over 0.2 s, not 1 s: beyond 0.2 s MuJoCo's stiffened runs
// leave the order-2 regime in tc (over 1 s the gaps at tc = 4e-4, 2e-4, 1e-4 fall by 4.20, 2.48 and
// extrapolate to 3.3e-5; at 2e-4, 1e-4, 5e-5 with h = 2.5e-5 by 2.49, 3.22, to 4.2e-6, 27.5 s of
// CPU; mbd at tol 1e-11 against 1e-13 9e-12, embedding against augmented 1.8e-10: docs/import.md).
TEST(ImportLoops, CassieLoopsAgreeWithMuJoCoStiffened) {
    const fs::path cassie = shared_models() / "cassie" / "cassie.xml";
    MjModelPtr m = compile(cassie);
    ASSERT_TRUE(m);
    auto [qvel, options] = initial_velocities(m.get());
    const std::set<std::string> hips = {"left-hip-roll", "left-hip-yaw", "left-hip-pitch",
                                        "right-hip-roll", "right-hip-yaw", "right-hip-pitch"};
    for (int j = 0; j < m->njnt; ++j) {
        const char* name = mj_id2name(m.get(), mjOBJ_JOINT, j);
        if (m->jnt_type[j] == mjJNT_FREE || (name && hips.count(name))) continue;
        for (int k = 0; k < (m->jnt_type[j] == mjJNT_BALL ? 3 : 1); ++k) qvel[m->jnt_dofadr[j] + k] = 0.0;
        if (name) options.joint_velocities.erase(name);
    }
    const StiffenedAgreement a = stiffened_agreement(cassie, qvel, options, 0.2, 5e-5, 4e-4);
    EXPECT_EQ(a.joints, 26u);  // 20 hinges, 2 balls, 4 loops
    EXPECT_GT(a.soft, 1e-2);   // the file's soft loops (solref 0.005 s) move cassie by centimetres
    expect_converges_to_mbd(a, 1e-6);
}

}  // namespace
}  // namespace mbd::test
