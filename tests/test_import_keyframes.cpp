// Issue 37, MJCF keyframes as named initial states (import/src/import.cpp apply_keyframe;
// docs/import.md): `--keyframe NAME` starts the scene at the keyframe's qpos and qvel. The oracle
// is MuJoCo itself started from the same keyframe (mj_resetDataKeyframe): every body's mass
// centre and axes at t = 0 (the keyframe's positions), and every body frame over 1 s of flight
// (the keyframe's velocities: a wrong one would show as a drift).
#include "support/mujoco_oracle.hpp"
#include "support/test_support.hpp"

#include <mbd/import/import.hpp>
#include <mbd/import/scene_writer.hpp>

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

namespace mbd::test {
namespace {

namespace fs = std::filesystem;

// A free torso carrying an arm on a hinge and a block on a slide; the keyframe places and turns
// the torso, bends the arm, moves the block and sets every velocity. A second keyframe is at rest.
const char* kMjcf = R"(<mujoco model="keyed">
  <option gravity="0 0 -9.81"/>
  <worldbody>
    <body name="torso" pos="0 0 1">
      <freejoint name="root"/>
      <inertial pos="0.02 0 0" mass="3" fullinertia="0.05 0.04 0.03 0.001 -0.002 0.003"/>
      <body name="arm" pos="0.2 0 0">
        <joint name="shoulder" type="hinge" axis="0 1 0.3"/>
        <inertial pos="0.15 0 0" mass="1" diaginertia="0.002 0.01 0.01"/>
      </body>
      <body name="block" pos="-0.1 0.1 0">
        <joint name="rail" type="slide" axis="1 0 0"/>
        <inertial pos="0 0 -0.05" mass="0.5" diaginertia="0.001 0.001 0.001"/>
      </body>
    </body>
  </worldbody>
  <keyframe>
    <key name="rest"/>
    <key name="tossed" qpos="0.1 -0.2 1.3 0.955336489125606 0.149834692583473 -0.224752038875209 0.119867754066778 0.5 0.1"
         qvel="0.3 -0.2 1.0 0.5 -0.4 0.8 2.0 -0.5"/>
  </keyframe>
</mujoco>
)";

fs::path model_file() {
    static const fs::path file = [] {
        const fs::path f = scratch("import_keyframes") / "keyed.xml";
        std::ofstream(f) << kMjcf;
        return f;
    }();
    return file;
}

TEST(ImportKeyframes, StartIsTheKeyframesStateAsMuJoCoHasIt) {
    MjModelPtr m = compile(model_file());
    ASSERT_TRUE(m);
    ASSERT_EQ(m->nkey, 2);
    const int key = mj_name2id(m.get(), mjOBJ_KEY, "tossed");
    import::ImportOptions options;
    options.keyframe = "tossed";
    const import::ImportedScene scene = import::import_model(model_file(), options);
    const Model model = load_scene_text(import::scene_yaml(scene), "keyed.yaml", shared_registry());
    const std::vector<double> qpos(m->key_qpos + key * m->nq, m->key_qpos + (key + 1) * m->nq);
    const std::vector<double> qvel(m->key_qvel + key * m->nv, m->key_qvel + (key + 1) * m->nv);
    std::vector<std::vector<double>> xpos, xmat, xipos;
    mujoco_samples(m.get(), qvel, 1e-4, 1.0, 0.01, [&](const mjData* d) {
        xpos.emplace_back(d->xpos, d->xpos + 3 * m->nbody);
        xmat.emplace_back(d->xmat, d->xmat + 9 * m->nbody);
        xipos.emplace_back(d->xipos, d->xipos + 3 * m->nbody);
    }, qpos);
    const std::vector<Eigen::VectorXd> q = mbd_run(model, 1.0, 0.01);
    // t = 0: mass centres and body axes where MuJoCo puts them at the keyframe
    double start = 0.0;
    for (const char* name : {"torso", "arm", "block"}) {
        const int mb = mj_name2id(m.get(), mjOBJ_BODY, name), b = model.body_index(name);
        const Vec3 centre(xipos[0][3 * mb], xipos[0][3 * mb + 1], xipos[0][3 * mb + 2]);
        const Mat3 axes = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(&xmat[0][9 * mb]);
        start = std::max({start, (q[0].segment<3>(7 * b) - centre).cwiseAbs().maxCoeff(),
                          (rotation_from_euler_parameters(q[0].segment<4>(7 * b + 3)) - axes).cwiseAbs().maxCoeff()});
    }
    int compared = 0;
    const double flight = body_frame_difference(m.get(), scene, model, q, xpos, xmat, compared);
    std::printf("keyframe 'tossed': start %.2e, 1 s of flight against MuJoCo %.2e (%d bodies)\n", start, flight, compared);
    EXPECT_EQ(compared, 3);
    EXPECT_LT(start, 1e-12);
    EXPECT_LT(flight, 1e-6);
}

TEST(ImportKeyframes, AnUnknownKeyframeIsRefusedListingTheKnownOnes) {
    const fs::path out = scratch("import_keyframes_bad") / "scene.yaml";
    const CommandResult r = run_mbd("import " + model_file().string() + " --keyframe squat -o " + out.string());
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("--keyframe squat: the MJCF file has no keyframe of that name (it has: rest, tossed)"), std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(out));
    const CommandResult ok = run_mbd("import " + model_file().string() + " --keyframe tossed -o " + out.string());
    EXPECT_EQ(ok.exit_code, 0) << ok.err;
}

}  // namespace
}  // namespace mbd::test
