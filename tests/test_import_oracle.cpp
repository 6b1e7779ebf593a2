// Issue 37, the import layer against MuJoCo: a model file imported into mbd (import/) moves as
// MuJoCo's own simulation of the same file does. MuJoCo runs RK4 at two steps (their difference
// shows its own error below 1e-9: order 4 on hinges, order 2 on a free root; for cassie three steps
// and their Richardson extrapolation, mujoco_extrapolated); mbd runs the embedding formulation (recursive path) with
// dop853 at tol 1e-11. Joint angles are compared in every hinge, the free root by its origin's
// position and its orientation, at every 0.01 s over 1 s, to 1e-6.
//
// Both sides have contacts, joint limits, equality constraints, actuators and passive forces
// off (opt.disableflags), and MuJoCo's damping, stiffness and armature set to zero in the
// compiled model that both read (mbd has no rotor inertia yet; docs/import.md).
#include "support/mujoco_oracle.hpp"
#include "support/test_support.hpp"

#include <mbd/import/import.hpp>
#include <mbd/import/mjcf_reader.hpp>
#include <mbd/import/scene_writer.hpp>
#include <mbd/import/urdf_reader.hpp>

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <cmath>
#include <tuple>
#include <cstdio>
#include <memory>

namespace mbd::test {
namespace {

namespace fs = std::filesystem;
using import::ImportedScene;

const fs::path kHumanoid = "/usr/share/mujoco/model/humanoid/humanoid.xml";  // Debian libmujoco-samples
const fs::path kSliderCrank = "/usr/share/mujoco/model/slider_crank/slider_crank.xml";
// MuJoCo's RK4 steps at which h and h / 2 differ by less than 1e-9 (order 4 on hinges and slides)
constexpr double kPandaUrdfStep = 2.5e-4, kDoublePendulumUrdfStep = 1.25e-4, kSliderCrankStep = 5e-4;

struct Agreement {
    double mujoco_self = 0.0;  // MuJoCo at h against h / 2
    double mbd = 0.0;          // mbd against MuJoCo at h / 2
};

// `m` (already set up with conservative_tree) imported into mbd from the compiled model
// (`scene` given) and both run over t_end (1 s unless given).
Agreement agreement(mjModel* m, const ImportedScene& scene, const std::vector<double>& qvel, double h, double t_end = 1.0) {
    const std::string yaml = import::scene_yaml(scene);
    const Model model = load_scene_text(yaml, "imported.yaml", shared_registry());
    const auto coarse = mujoco_run(m, qvel, h, t_end, 0.01);
    const auto fine = mujoco_run(m, qvel, h / 2, t_end, 0.01);
    const std::vector<Eigen::VectorXd> q = mbd_run(model, t_end, 0.01);
    return {max_difference(coarse, fine), trajectory_difference(m, scene, model, q, fine)};
}

TEST(ImportOracle, HumanoidAgreesWithMuJoCo) {
    MjModelPtr m = compile(kHumanoid);
    ASSERT_TRUE(m);
    ASSERT_EQ(m->njnt, 22);  // a free root and 21 hinges
    conservative_tree(m.get());
    const auto [qvel, options] = initial_velocities(m.get());
    import::SourceTree tree = import::read_mjcf_model(m.get(), kHumanoid.string());
    import::apply_joint_velocities(tree, options);
    const ImportedScene scene = import::build_scene(tree);
    // 21 hinges in 16 bodies: head and hands welded (merged), 9 frame bodies between the hinges
    // of one body (waist 1, thighs 2 + 2, feet 1 + 1, upper arms 1 + 1)
    EXPECT_EQ(scene.joints.size(), 21u);
    EXPECT_EQ(scene.bodies.size(), 13u + 9u);
    // MuJoCo's RK4 is of order 2 on a free root's orientation (its stages compose the quaternion
    // with the exponential of each stage's velocity): the difference of h and h / 2 fell by 4.0
    // per halving from h = 5e-4 (7.4e-7) to 6.25e-5 (1.2e-8). The error of the h / 2 run is then
    // a third of the difference; at h = 2e-5 it is below 1e-9.
    const Agreement a = agreement(m.get(), scene, qvel, 2e-5);
    std::printf("humanoid: MuJoCo RK4 h = 2e-5 against 1e-5: %.3g; mbd against MuJoCo: %.3g\n", a.mujoco_self, a.mbd);
    EXPECT_LT(a.mujoco_self / 3, 1e-9);
    EXPECT_LT(a.mbd, 1e-6);
}

// The same humanoid with its armature kept (0.01 kg m^2 on every hinge, the file's default class;
// MuJoCo adds it to the joint's diagonal of the joint-space mass matrix): each hinge gets a rotor
// pinned to the ground and coupled one to one to its angle (scene_builder.cpp add_rotor). Every
// hinge's parent moves (the root is free), so the rotor must add 1/2 I_a qdot^2 and nothing else.
// Without the rotors the armature changes the motion by far more than 1e-6 (printed).
TEST(ImportOracle, HumanoidWithArmatureAgreesWithMuJoCo) {
    MjModelPtr m = compile(kHumanoid);
    ASSERT_TRUE(m);
    conservative_tree(m.get(), /*keep_armature=*/true);
    ASSERT_EQ(m->dof_armature[6], 0.01);
    const auto [qvel, options] = initial_velocities(m.get());
    import::SourceTree tree = import::read_mjcf_model(m.get(), kHumanoid.string());
    import::apply_joint_velocities(tree, options);
    const ImportedScene scene = import::build_scene(tree);
    EXPECT_EQ(scene.couplings.size(), 21u);
    EXPECT_EQ(scene.joints.size(), 42u);  // 21 hinges and the 21 rotors' pins
    const Agreement a = agreement(m.get(), scene, qvel, 2e-5);
    for (import::SourceBody& body : tree.bodies)
        for (import::SourceJoint& joint : body.joints) joint.armature = 0.0;
    const ImportedScene no_rotors = import::build_scene(tree);
    const Model without = load_scene_text(import::scene_yaml(no_rotors), "no-rotors.yaml", shared_registry());
    const double effect = trajectory_difference(m.get(), no_rotors, without, mbd_run(without, 1.0, 0.01),
                                                mujoco_run(m.get(), qvel, 5e-4, 1.0, 0.01));  // coarse: the effect is large
    std::printf("humanoid with armature: MuJoCo RK4 h = 2e-5 against 1e-5: %.3g; mbd against MuJoCo: %.3g; "
                "without the rotors: %.3g\n", a.mujoco_self, a.mbd, effect);
    EXPECT_LT(a.mujoco_self / 3, 1e-9);
    EXPECT_LT(a.mbd, 1e-6);
    EXPECT_GT(effect, 1e-3);
}

// A second real file from libmujoco-samples: the slider-crank demonstration, three unnamed hinges
// (a crank with a coupler, and a lone crank) whose inertias MuJoCo computes from their capsules.
// Its slider-crank actuators and sites have no mbd equivalent: the import lists them in its one
// warning. Hinge k turns at (-1)^k (1 + 0.1 k) rad/s (initial_velocities); the joints' damping is
// off on both sides (conservative_tree).
TEST(ImportOracle, SliderCrankSampleAgreesWithMuJoCo) {
    MjModelPtr m = compile(kSliderCrank);
    ASSERT_TRUE(m);
    ASSERT_EQ(m->njnt, 3);
    conservative_tree(m.get());
    const auto [qvel, options] = initial_velocities(m.get());
    import::SourceTree tree = import::read_mjcf_model(m.get(), kSliderCrank.string());
    import::apply_joint_velocities(tree, options);
    const ImportedScene scene = import::build_scene(tree);
    EXPECT_EQ(scene.joints.size(), 3u);
    const std::string warning = import::unmapped_summary(scene.unmapped);
    for (const char* left_out : {"actuators", "forward", "backward", "broken", "sites", "cranksite", "slidersite"})
        EXPECT_NE(warning.find(left_out), std::string::npos) << left_out << " not in: " << warning;
    const Agreement a = agreement(m.get(), scene, qvel, kSliderCrankStep);
    std::printf("slider-crank (libmujoco-samples): MuJoCo RK4 h = %g against %g: %.3g; mbd against MuJoCo: %.3g\n",
                kSliderCrankStep, kSliderCrankStep / 2, a.mujoco_self, a.mbd);
    EXPECT_LT(a.mujoco_self, 1e-9);
    EXPECT_LT(a.mbd, 1e-6);
}

// A URDF robot from ../shared/models: mbd reads the file with urdfdom, MuJoCo with its own URDF
// reader a copy without <visual> and <collision> (urdf_without_geometry). The documented state:
// initial_velocities of MuJoCo's joints, limits, damping and couplings off on both sides (mbd:
// conservative_source_tree; MuJoCo: conservative_tree, its equality constraints, where its reader
// makes a <mimic> one, disabled), the root link welded to the world as both readers weld it.
// With `mujocos_inertias`, mbd imports MuJoCo's compiled model of the copy instead (read_mjcf_model):
// the same bodies with MuJoCo's principal inertias (see PandaUrdfAgreesWithMuJoCo).
Agreement urdf_agreement(const fs::path& urdf, const std::string& folder, double h, size_t joints,
                         bool mujocos_inertias = false) {
    const fs::path copy = urdf_without_geometry(urdf, folder);
    MjModelPtr m = compile(copy);
    if (!m) return {1.0, 1.0};
    conservative_tree(m.get());
    const auto [qvel, options] = initial_velocities(m.get());
    import::SourceTree tree = mujocos_inertias ? import::read_mjcf_model(m.get(), copy.string()) : import::read_model_file(urdf);
    conservative_source_tree(tree);
    import::apply_joint_velocities(tree, options);
    const ImportedScene scene = import::build_scene(tree);
    EXPECT_EQ(scene.joints.size(), joints) << urdf;
    return agreement(m.get(), scene, qvel, h);
}

TEST(ImportOracle, Ur5UrdfAgreesWithMuJoCo) {
    const Agreement a = urdf_agreement(shared_models() / "erd_ur5" / "ur5_robot.urdf", "import_ur5", 5e-4, 6);
    std::printf("ur5 (URDF): MuJoCo RK4 h = 5e-4 against 2.5e-4: %.3g; mbd against MuJoCo: %.3g\n", a.mujoco_self, a.mbd);
    EXPECT_LT(a.mujoco_self, 1e-9);
    EXPECT_LT(a.mbd, 1e-6);
}

// example-robot-data's panda: 7 revolute joints, two prismatic fingers (the second a <mimic> of
// the first, left out on both sides: the fingers slide freely, pushed by the arm's turning), the
// fixed links panda_link8, panda_hand and panda_hand_tcp fused into panda_link7. Its inertias
// have products of inertia, which MuJoCo's compiler turns into principal moments and axes
// (mju_eig3) to about 5e-7: panda_link1's iyz 0.019169 comes back as 0.01916946 from MuJoCo's
// body_inertia and body_iquat. That alone moves the joints by about 1e-5 over 1 s, so mbd's run
// of the file (urdfdom, the file's exact tensors; DartAgreement.PandaUrdf* checks it against
// DART to 1e-6) is held to 1e-4 of MuJoCo's, and mbd's run of MuJoCo's compiled model of the same
// file (its bodies, joints and principal inertias) to 1e-6.
TEST(ImportOracle, PandaUrdfAgreesWithMuJoCo) {
    const fs::path urdf = shared_models() / "erd_panda" / "panda.urdf";
    MjModelPtr m = compile(urdf_without_geometry(urdf, "import_erd_panda_inertia"));
    ASSERT_TRUE(m);
    const int link1 = mj_name2id(m.get(), mjOBJ_BODY, "panda_link1");
    ASSERT_GE(link1, 0);
    Mat3 axes;
    mju_quat2Mat(axes.data(), m->body_iquat + 4 * link1);  // row-major into column-major: the transpose
    const Mat3 mujoco = axes.transpose() * Vec3(m->body_inertia + 3 * link1).asDiagonal() * axes;
    const double file_iyz = 0.019169;  // panda.urdf, panda_link1 <inertia iyz>
    const double eig_error = std::abs(mujoco(1, 2) - file_iyz);
    const Agreement file = urdf_agreement(urdf, "import_erd_panda", kPandaUrdfStep, 9);
    const Agreement compiled = urdf_agreement(urdf, "import_erd_panda_compiled", kPandaUrdfStep, 9, /*mujocos_inertias=*/true);
    std::printf("panda (URDF): MuJoCo RK4 h = %g against %g: %.3g; MuJoCo's panda_link1 iyz off the file's by %.3g; "
                "mbd against MuJoCo: from the file %.3g, from MuJoCo's compiled model %.3g\n",
                kPandaUrdfStep, kPandaUrdfStep / 2, file.mujoco_self, eig_error, file.mbd, compiled.mbd);
    EXPECT_GT(eig_error, 1e-7);
    EXPECT_LT(file.mujoco_self, 1e-9);
    EXPECT_LT(file.mbd, 1e-4);
    EXPECT_LT(compiled.mbd, 1e-6);
}

// example-robot-data's planar double pendulum: two revolute joints about x, off-diagonal
// inertias, swinging under gravity; its limits (lower = upper = 0) and damping left out.
TEST(ImportOracle, DoublePendulumUrdfAgreesWithMuJoCo) {
    const Agreement a = urdf_agreement(shared_models() / "erd_double_pendulum" / "double_pendulum.urdf",
                                       "import_erd_double_pendulum", kDoublePendulumUrdfStep, 2);
    std::printf("double pendulum (URDF): MuJoCo RK4 h = %g against %g: %.3g; mbd against MuJoCo: %.3g\n",
                kDoublePendulumUrdfStep, kDoublePendulumUrdfStep / 2, a.mujoco_self, a.mbd);
    EXPECT_LT(a.mujoco_self, 1e-9);
    EXPECT_LT(a.mbd, 1e-6);
}

// The menagerie MJCF models of ../shared/models, whose meshes are missing on purpose: both sides
// compile them as the import does (import::compile_mjcf: placeholder meshes through MuJoCo's
// virtual file system; every body's inertia is explicit, so no placeholder enters the dynamics)
// and run them from qpos0 with the documented velocities (initial_velocities). Equality
// constraints are off on both sides (conservative_tree; the import's couplings and loops left out:
// the panda's finger coupling, cassie's four `connect` loops, which MuJoCo keeps soft).
struct MenagerieModel {
    MjModelPtr m{nullptr, mj_deleteModel};
    std::vector<double> qvel;
    ImportedScene scene;
};

MenagerieModel menagerie_model(const fs::path& file, size_t joints) {
    MenagerieModel out;
    out.m = compile(file);
    if (!out.m) return out;
    conservative_tree(out.m.get());
    import::ImportOptions options;
    std::tie(out.qvel, options) = initial_velocities(out.m.get());
    import::SourceTree tree = import::read_mjcf_model(out.m.get(), file.string());
    import::apply_joint_velocities(tree, options);
    tree.couplings.clear();
    tree.loops.clear();
    out.scene = import::build_scene(tree);
    EXPECT_EQ(out.scene.joints.size(), joints) << file;
    return out;
}

Agreement menagerie_agreement(const fs::path& file, double h, size_t joints) {
    MenagerieModel c = menagerie_model(file, joints);
    if (!c.m) return {1.0, 1.0};
    return agreement(c.m.get(), c.scene, c.qvel, h);
}

// 7 hinges and the two fingers' slides (pushed out by the arm's turning: limits are off). RK4 is
// of order 4 on hinges and slides (h and h / 2 differ by 9.4e-9 at h = 5e-4, 5.9e-10 at 2.5e-4).
TEST(ImportOracle, MenageriePandaAgreesWithMuJoCo) {
    const Agreement a = menagerie_agreement(shared_models() / "panda" / "panda.xml", 2.5e-4, 9);
    std::printf("panda (MJCF): MuJoCo RK4 h = 2.5e-4 against 1.25e-4: %.3g; mbd against MuJoCo: %.3g\n", a.mujoco_self, a.mbd);
    EXPECT_LT(a.mujoco_self, 1e-9);
    EXPECT_LT(a.mbd, 1e-6);
}

// 6 hinges (h and h / 2 differ by 4.3e-9 at h = 5e-4, 2.4e-10 at 2.5e-4).
TEST(ImportOracle, MenagerieUr5eAgreesWithMuJoCo) {
    const Agreement a = menagerie_agreement(shared_models() / "ur5e" / "ur5e.xml", 2.5e-4, 6);
    std::printf("ur5e (MJCF): MuJoCo RK4 h = 2.5e-4 against 1.25e-4: %.3g; mbd against MuJoCo: %.3g\n", a.mujoco_self, a.mbd);
    EXPECT_LT(a.mujoco_self, 1e-9);
    EXPECT_LT(a.mbd, 1e-6);
}

// A free pelvis, 2 ball joints and 20 hinges, its loops open (above), over 1 s. MuJoCo's RK4 is of
// order 2 on the free root, so a plain run would need h = 2e-5 for its error below 1e-9 (17 s
// here); instead MuJoCo runs at h = 5e-4, h / 2, h / 4 and the oracle is the Richardson
// extrapolation of the last two (mujoco_extrapolated): its order (the differences fall by 4.00 per
// halving) and its own error (the two extrapolations differ by 8.7e-11; their difference fell by
// 16 from h = 1e-3, so the remainder is of order 4 and the oracle's error about 6e-12) asserted.
// mbd's own error: its run at tol 1e-11 against tol 1e-13 (2.3e-11 in the bodies' coordinates).
constexpr double kCassieStep = 5e-4;

TEST(ImportOracle, MenagerieCassieTreeAgreesWithMuJoCo) {
    MenagerieModel c = menagerie_model(shared_models() / "cassie" / "cassie.xml", 22);
    ASSERT_TRUE(c.m);
    const Model model = load_scene_text(import::scene_yaml(c.scene), "cassie.yaml", shared_registry());
    const ExtrapolatedRun mujoco = mujoco_extrapolated(c.m.get(), c.qvel, kCassieStep, 1.0, 0.01);
    const std::vector<Eigen::VectorXd> q = mbd_run(model, 1.0, 0.01), tight = mbd_run(model, 1.0, 0.01, "embedding", 1e-13);
    double mbd_self = 0.0;
    for (size_t s = 0; s < q.size() && s < tight.size(); ++s) mbd_self = std::max(mbd_self, (q[s] - tight[s]).cwiseAbs().maxCoeff());
    const double gap = trajectory_difference(c.m.get(), c.scene, model, q, mujoco.qpos);
    const double gap_tight = trajectory_difference(c.m.get(), c.scene, model, tight, mujoco.qpos);
    std::printf("cassie (MJCF, loops open, 1 s): MuJoCo RK4 h = %g, h/2, h/4 differ by %.3g, %.3g (ratio %.2f); "
                "extrapolations differ by %.3g; mbd tol 1e-11 against 1e-13: %.3g; mbd against MuJoCo extrapolated: %.3g "
                "(tol 1e-13: %.3g)\n",
                kCassieStep, mujoco.steps[0], mujoco.steps[1], mujoco.order_ratio(), mujoco.estimate, mbd_self, gap, gap_tight);
    EXPECT_GT(mujoco.order_ratio(), 3.5);
    EXPECT_LT(mujoco.order_ratio(), 4.5);
    EXPECT_LT(mujoco.estimate, 1e-9);
    EXPECT_LT(mbd_self, 1e-9);
    EXPECT_LT(gap, 1e-6);
}

}  // namespace
}  // namespace mbd::test
