// MuJoCo as the oracle of the import tests (issue 37; tests/test_import_*.cpp): a model compiled
// by MuJoCo and run with its RK4, and the same model imported into mbd and run with dop853, both
// sampled on the same times. Header-only: only the import tests link MuJoCo (through mbd_import).
#pragma once

#include "support/test_support.hpp"

#include <mbd/import/imported_scene.hpp>
#include <mbd/import/mjcf_compile.hpp>

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <cmath>
#include <functional>
#include <memory>
#include <regex>

namespace mbd::test {

// ../shared/models beside the repository (docs/import.md): the real models of the tests.
inline std::filesystem::path shared_models() {
    const std::filesystem::path dir = source_dir() / ".." / "shared" / "models";
    if (!std::filesystem::is_directory(dir))
        ADD_FAILURE() << "the shared models folder " << dir << " is missing (it lies beside the repository)";
    return dir;
}

// A copy of a URDF without <visual> and <collision>, in the scratch folder `folder`, for the peers
// (MuJoCo, DART) whose readers cannot resolve the package:// meshes, missing on purpose. URDF
// inertias are explicit, so geometry does not enter the dynamics.
inline std::filesystem::path urdf_without_geometry(const std::filesystem::path& urdf, const std::string& folder) {
    const std::regex geometry("<visual>[\\s\\S]*?</visual>|<collision>[\\s\\S]*?</collision>");
    return write_text(scratch(folder) / urdf.filename(), std::regex_replace(read_text(urdf), geometry, ""));
}

// The comparisons' mbd side of a source tree as the peers run it: no joint stops, springs or damping, no
// couplings (URDF mimic, MJCF equality joint) and no loop constraints (the peers' are switched off).
inline void conservative_source_tree(import::SourceTree& tree) {
    for (import::SourceBody& body : tree.bodies)
        for (import::SourceJoint& joint : body.joints) joint.limited = false, joint.damping = joint.stiffness = 0.0;
    tree.couplings.clear();
    tree.loops.clear();
}

using MjModelPtr = std::unique_ptr<mjModel, void (*)(mjModel*)>;

// The file compiled as the import compiles it (import::compile_mjcf: placeholders for missing
// meshes, refused when a body's inertia would come from one).
inline MjModelPtr compile(const std::filesystem::path& file) {
    import::MjcfCompilation compiled = import::compile_mjcf(file);
    EXPECT_TRUE(compiled.model) << file << ": " << compiled.error;
    return std::move(compiled.model);
}

// Calls `at_sample` with MuJoCo's data at t = 0 and every `sample` s to t_end, from qpos (qpos0
// when empty) with velocity qvel, RK4 at step h.
inline void mujoco_samples(mjModel* m, const std::vector<double>& qvel, double h, double t_end, double sample,
                           const std::function<void(const mjData*)>& at_sample, const std::vector<double>& qpos = {}) {
    m->opt.integrator = mjINT_RK4;
    m->opt.timestep = h;
    std::unique_ptr<mjData, void (*)(mjData*)> d(mj_makeData(m), mj_deleteData);
    mj_resetData(m, d.get());
    std::copy(qvel.begin(), qvel.end(), d->qvel);
    std::copy(qpos.begin(), qpos.end(), d->qpos);
    mj_forward(m, d.get());
    at_sample(d.get());
    const long per_sample = std::lround(sample / h), samples = std::lround(t_end / sample);
    for (long s = 0; s < samples; ++s) {
        for (long k = 0; k < per_sample; ++k) mj_step(m, d.get());
        mj_forward(m, d.get());  // positions of the bodies at the state reached
        at_sample(d.get());
    }
}

// qpos every `sample` s to t_end (mujoco_samples).
inline std::vector<std::vector<double>> mujoco_run(mjModel* m, const std::vector<double>& qvel, double h, double t_end,
                                                   double sample) {
    std::vector<std::vector<double>> out;
    mujoco_samples(m, qvel, h, t_end, sample, [&](const mjData* d) { out.emplace_back(d->qpos, d->qpos + m->nq); });
    return out;
}

// The world frames of MuJoCo's bodies (xpos, xmat) every `sample` s to t_end (mujoco_samples).
struct MujocoFrames {
    std::vector<std::vector<double>> xpos, xmat;
};

inline MujocoFrames mujoco_frames(mjModel* m, const std::vector<double>& qvel, double h, double t_end, double sample) {
    MujocoFrames out;
    mujoco_samples(m, qvel, h, t_end, sample, [&](const mjData* d) {
        out.xpos.emplace_back(d->xpos, d->xpos + 3 * m->nbody);
        out.xmat.emplace_back(d->xmat, d->xmat + 9 * m->nbody);
    });
    return out;
}

inline double max_difference(const std::vector<std::vector<double>>& a, const std::vector<std::vector<double>>& b) {
    double worst = 0.0;
    for (size_t s = 0; s < a.size() && s < b.size(); ++s)
        for (size_t k = 0; k < a[s].size(); ++k) worst = std::max(worst, std::abs(a[s][k] - b[s][k]));
    return worst;
}

// mbd's body poses every `sample` s: q of every output row (dop853 at tol 1e-11).
inline std::vector<Eigen::VectorXd> mbd_run(const Model& model, double t_end, double sample,
                                            const std::string& formulation = "embedding") {
    std::vector<Eigen::VectorXd> out;
    simulate(model, shared_registry(), adaptive_run(formulation, "dop853", 1e-11, t_end, sample),
             [&](const SimulationSample& s) {
                 out.push_back(s.state.q);
                 return true;
             });
    return out;
}

// How far one body frame of mbd (origin, axes) lies from MuJoCo's body `mb` in one sample
// (xpos, xmat rows): the largest coordinate difference of the origins, or the angle of the
// rotation between the two axes, whichever is larger.
inline double frame_gap(const Vec3& origin, const Mat3& axes, const std::vector<double>& xpos,
                        const std::vector<double>& xmat, int mb) {
    const Mat3 mj_axes = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(&xmat[9 * mb]);
    const Vec4 e = euler_parameters_from_rotation(mj_axes.transpose() * axes);
    return std::max((origin - Vec3(&xpos[3 * mb])).cwiseAbs().maxCoeff(), 2.0 * std::asin(std::min(1.0, e.tail<3>().norm())));
}

// World frames of the bodies MuJoCo and the imported scene share by name (a merged or frame body
// is not compared), every sample: the largest difference of a body frame's origin (MuJoCo's
// xpos; mbd's mass centre plus the offset it had at t = 0, turned with the body) and of its
// orientation (angle of the rotation between MuJoCo's xmat and mbd's body axes). `compared`
// receives how many bodies were compared.
inline double body_frame_difference(const mjModel* m, const import::ImportedScene& scene, const Model& model,
                                    const std::vector<Eigen::VectorXd>& q, const std::vector<std::vector<double>>& xpos,
                                    const std::vector<std::vector<double>>& xmat, int& compared) {
    double worst = 0.0;
    compared = 0;
    EXPECT_EQ(q.size(), xpos.size());
    for (const import::SceneBody& body : scene.bodies) {
        const int mb = mj_name2id(m, mjOBJ_BODY, body.name.c_str());
        if (mb < 0 || body.frame) continue;
        const int b = model.body_index(body.name);
        const Mat3 A0 = rotation_from_euler_parameters(q[0].segment<4>(7 * b + 3));
        const Vec3 offset = A0.transpose() * (Vec3(&xpos[0][3 * mb]) - q[0].segment<3>(7 * b));
        for (size_t s = 0; s < q.size() && s < xpos.size(); ++s) {
            const Mat3 A = rotation_from_euler_parameters(q[s].segment<4>(7 * b + 3).normalized());
            worst = std::max(worst, frame_gap(q[s].segment<3>(7 * b) + A * offset, A, xpos[s], xmat[s], mb));
        }
        ++compared;
    }
    return worst;
}

}  // namespace mbd::test
