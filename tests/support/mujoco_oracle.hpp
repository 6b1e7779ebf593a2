// MuJoCo as the oracle of the import tests (issue 37; tests/test_import_*.cpp): a model compiled
// by MuJoCo and run with its RK4, and the same model imported into mbd and run with dop853, both
// sampled on the same times. Header-only: only the import tests link MuJoCo (through mbd_import).
#pragma once

#include "support/test_support.hpp"

#include <mbd/import/import.hpp>
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

inline double max_difference(const std::vector<std::vector<double>>& a, const std::vector<std::vector<double>>& b) {
    double worst = 0.0;
    for (size_t s = 0; s < a.size() && s < b.size(); ++s)
        for (size_t k = 0; k < a[s].size(); ++k) worst = std::max(worst, std::abs(a[s][k] - b[s][k]));
    return worst;
}

// MuJoCo's RK4 is of order 2 on a free root's orientation (its stages compose the quaternion with
// the exponential of each stage's velocity), so its error at step h is c h^2 + O(h^3): Richardson
// extrapolation R(h) = x(h/2) + (x(h/2) - x(h)) / 3 of two runs removes the h^2 term. Three runs
// (h, h/2, h/4) give two extrapolations; the oracle is R(h/2) and |R(h) - R(h/2)| bounds its error
// (with a remainder of order p >= 1 it is (2^p - 1) times that error). Quaternions (free and ball
// joints) are normalised after extrapolation.
struct ExtrapolatedRun {
    std::vector<std::vector<double>> qpos;  // R(h/2) every sample
    double steps[2] = {0, 0};               // max |x(h) - x(h/2)|, max |x(h/2) - x(h/4)|
    double estimate = 0.0;                  // max |R(h) - R(h/2)|: the error bound of qpos
    double order_ratio() const { return steps[0] / steps[1]; }  // 4 for order 2
};

inline std::vector<std::vector<double>> richardson_order2(const mjModel* m, const std::vector<std::vector<double>>& coarse,
                                                          const std::vector<std::vector<double>>& fine) {
    auto out = fine;
    for (size_t s = 0; s < out.size() && s < coarse.size(); ++s) {
        for (size_t k = 0; k < out[s].size(); ++k) out[s][k] += (fine[s][k] - coarse[s][k]) / 3;
        for (int j = 0; j < m->njnt; ++j) {
            if (m->jnt_type[j] != mjJNT_FREE && m->jnt_type[j] != mjJNT_BALL) continue;
            mju_normalize4(&out[s][m->jnt_qposadr[j] + (m->jnt_type[j] == mjJNT_FREE ? 3 : 0)]);
        }
    }
    return out;
}

inline ExtrapolatedRun mujoco_extrapolated(mjModel* m, const std::vector<double>& qvel, double h, double t_end, double sample) {
    const auto x1 = mujoco_run(m, qvel, h, t_end, sample), x2 = mujoco_run(m, qvel, h / 2, t_end, sample),
               x4 = mujoco_run(m, qvel, h / 4, t_end, sample);
    ExtrapolatedRun out;
    out.steps[0] = max_difference(x1, x2), out.steps[1] = max_difference(x2, x4);
    out.qpos = richardson_order2(m, x2, x4);
    out.estimate = max_difference(richardson_order2(m, x1, x2), out.qpos);
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

// mbd's body poses every `sample` s: q of every output row (dop853 at tol 1e-11 unless given).
inline std::vector<Eigen::VectorXd> mbd_run(const Model& model, double t_end, double sample,
                                            const std::string& formulation = "embedding", double tolerance = 1e-11) {
    std::vector<Eigen::VectorXd> out;
    simulate(model, shared_registry(), adaptive_run(formulation, "dop853", tolerance, t_end, sample),
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

// MuJoCo's index of the joint the import named `name`: by name, or an unnamed one as the scene
// names it ("joint #N" in mjcf_reader.cpp, written joint__N); -1 when MuJoCo has none.
inline int mujoco_joint(const mjModel* m, const std::string& name) {
    const int j = mj_name2id(m, mjOBJ_JOINT, name.c_str());
    const std::string unnamed = "joint__";  // "joint #N" as a scene name
    if (j >= 0 || name.compare(0, unnamed.size(), unnamed) != 0) return j;
    const int n = std::stoi(name.substr(unnamed.size()));
    return n < m->njnt && !mj_id2name(m, mjOBJ_JOINT, n) ? n : -1;
}

// The comparison's settings on both sides: RK4, no contact, limit, equality, actuation,
// friction loss or passive force; zero damping, stiffness and (unless kept) armature.
inline void conservative_tree(mjModel* m, bool keep_armature = false) {
    m->opt.integrator = mjINT_RK4;
    m->opt.disableflags |= mjDSBL_CONTACT | mjDSBL_LIMIT | mjDSBL_EQUALITY | mjDSBL_ACTUATION |
                           mjDSBL_FRICTIONLOSS | mjDSBL_PASSIVE;
    for (int k = 0; k < m->nv; ++k) {
        m->dof_damping[k] = m->dof_frictionloss[k] = 0.0;
        if (!keep_armature) m->dof_armature[k] = 0.0;
    }
    for (int j = 0; j < m->njnt; ++j) m->jnt_stiffness[j] = 0.0, m->jnt_limited[j] = 0;  // no stops imported either
}

// The documented initial velocities: hinge number k (MuJoCo's joint order, from 0) turns at
// (-1)^k (1 + 0.1 k) rad/s; a free joint moves its origin at (0.3, -0.2, 1.0) m/s and turns at
// (0.5, -0.4, 0.8) rad/s in its body axes. Returned as qvel and as the import's options.
inline std::pair<std::vector<double>, import::ImportOptions> initial_velocities(const mjModel* m) {
    std::vector<double> qvel(m->nv, 0.0);
    import::ImportOptions options;
    int hinge = 0;
    for (int j = 0; j < m->njnt; ++j) {
        const int d = m->jnt_dofadr[j];
        std::vector<double> v;
        if (m->jnt_type[j] == mjJNT_FREE) v = {0.3, -0.2, 1.0, 0.5, -0.4, 0.8};
        if (m->jnt_type[j] == mjJNT_HINGE) v = {(hinge % 2 ? -1.0 : 1.0) * (1.0 + 0.1 * hinge)}, ++hinge;
        for (size_t k = 0; k < v.size(); ++k) qvel[d + k] = v[k];
        const char* name = mj_id2name(m, mjOBJ_JOINT, j);  // an unnamed one as the import names it
        if (!v.empty()) options.joint_velocities[name ? std::string(name) : "joint #" + std::to_string(j)] = v;
    }
    return {qvel, options};
}

inline Mat3 body_rotation(const Model& model, const Eigen::VectorXd& q, int scene_body, const import::ImportedScene& scene) {
    if (scene_body < 0) return Mat3::Identity();
    const int b = model.body_index(scene.bodies[scene_body].name);
    return rotation_from_euler_parameters(q.segment<4>(7 * b + 3));
}

inline Vec3 body_position(const Model& model, const Eigen::VectorXd& q, int scene_body, const import::ImportedScene& scene) {
    if (scene_body < 0) return Vec3::Zero();
    return q.segment<3>(7 * model.body_index(scene.bodies[scene_body].name));
}

// How far mbd's one-freedom joint `joint` moved from state q0 to q: a hinge's angle from the
// relative rotation of its two bodies about its axis, a slide's travel from the child's mass
// centre in the parent's axes (it moves along the axis there).
inline double scene_joint_travel(const import::SceneJoint& joint, bool slide, const import::ImportedScene& scene,
                                 const Model& model, const Eigen::VectorXd& q0, const Eigen::VectorXd& q) {
    const Mat3 parent0 = body_rotation(model, q0, joint.parent, scene), parent = body_rotation(model, q, joint.parent, scene);
    const Vec3 axis = parent0.transpose() * joint.axis;
    if (slide) {
        const Vec3 at0 = parent0.transpose() * (body_position(model, q0, joint.child, scene) - body_position(model, q0, joint.parent, scene));
        const Vec3 at = parent.transpose() * (body_position(model, q, joint.child, scene) - body_position(model, q, joint.parent, scene));
        return axis.dot(at - at0);
    }
    const Mat3 rel0 = parent0.transpose() * body_rotation(model, q0, joint.child, scene);
    const Mat3 relative = parent.transpose() * body_rotation(model, q, joint.child, scene);
    const Vec4 e = euler_parameters_from_rotation(relative * rel0.transpose());
    return 2.0 * std::atan2(e.tail<3>().dot(axis), e[0]);
}

// How far mbd's joint `joint` (MuJoCo's joint j) lies from MuJoCo's coordinates in sample s: a
// hinge's angle or a slide's travel (scene_joint_travel, zero at qpos0), a ball's rotation angle
// between MuJoCo's quaternion and the relative rotation of the bodies.
inline double joint_gap(const mjModel* m, int j, const import::SceneJoint& joint, const import::ImportedScene& scene, const Model& model,
                 const Eigen::VectorXd& q0, const Eigen::VectorXd& q, const std::vector<double>& qpos) {
    const int adr = m->jnt_qposadr[j];
    if (m->jnt_type[j] == mjJNT_SLIDE)
        return std::abs(scene_joint_travel(joint, true, scene, model, q0, q) - (qpos[adr] - m->qpos0[adr]));
    if (m->jnt_type[j] == mjJNT_BALL) {  // MuJoCo: child axes = parent axes * body_quat * qpos (unit at qpos0)
        const Mat3 parent0 = body_rotation(model, q0, joint.parent, scene), parent = body_rotation(model, q, joint.parent, scene);
        const Mat3 rel0 = parent0.transpose() * body_rotation(model, q0, joint.child, scene);
        const Mat3 relative = parent.transpose() * body_rotation(model, q, joint.child, scene);
        const Vec4 mj(qpos[adr], -qpos[adr + 1], -qpos[adr + 2], -qpos[adr + 3]);
        const Vec4 mismatch = quaternion_product(mj, euler_parameters_from_rotation(rel0.transpose() * relative));
        return 2.0 * std::asin(std::min(1.0, mismatch.tail<3>().norm()));
    }
    EXPECT_EQ(m->jnt_type[j], mjJNT_HINGE) << joint.name;
    return std::abs(wrap_angle(scene_joint_travel(joint, false, scene, model, q0, q) - (qpos[adr] - m->qpos0[adr])));
}

// A joint of the scene that stands for an MJCF equality constraint (scene_builder.cpp add_loop).
inline bool closes_a_loop(const import::SceneJoint& joint) {
    return joint.comment.find("(closes a loop)") != std::string::npos;
}

// The largest difference between mbd and MuJoCo over the samples: every hinge, slide and ball
// (joint_gap) and a free root's origin and orientation (rotation angle of MuJoCo's quaternion to mbd's).
inline double trajectory_difference(const mjModel* m, const import::ImportedScene& scene, const Model& model,
                             const std::vector<Eigen::VectorXd>& q, const std::vector<std::vector<double>>& qpos) {
    double worst = 0.0;
    EXPECT_EQ(q.size(), qpos.size());
    int compared = 0;
    for (const import::SceneJoint& joint : scene.joints) {
        if (closes_a_loop(joint)) continue;  // an equality constraint: MuJoCo has no joint for it
        const int j = mujoco_joint(m, joint.name);
        if (j < 0 && joint.name.size() > 10 && joint.name.substr(joint.name.size() - 10) == "_rotor_pin") continue;  // armature
        EXPECT_GE(j, 0) << joint.name;
        if (j < 0) continue;
        for (size_t s = 0; s < q.size() && s < qpos.size(); ++s)
            worst = std::max(worst, joint_gap(m, j, joint, scene, model, q[0], q[s], qpos[s]));
        ++compared;
    }
    for (int j = 0; j < m->njnt; ++j) {
        if (m->jnt_type[j] != mjJNT_FREE) continue;
        const int body = m->jnt_bodyid[j], adr = m->jnt_qposadr[j];
        const int sb = scene.body_of_source[body - 1];
        const int b = model.body_index(scene.bodies[sb].name);
        // the body frame's origin in mbd: its mass centre plus the offset it had at t = 0
        const Mat3 A0 = rotation_from_euler_parameters(q[0].segment<4>(7 * b + 3));
        const Vec3 offset = A0.transpose() * (Vec3(qpos[0][adr], qpos[0][adr + 1], qpos[0][adr + 2]) - q[0].segment<3>(7 * b));
        for (size_t s = 0; s < q.size() && s < qpos.size(); ++s) {
            const Vec4 e = q[s].segment<4>(7 * b + 3);
            const Vec3 origin = q[s].segment<3>(7 * b) + rotation_from_euler_parameters(e) * offset;
            worst = std::max(worst, (origin - Vec3(qpos[s][adr], qpos[s][adr + 1], qpos[s][adr + 2])).cwiseAbs().maxCoeff());
            const Vec4 mj(qpos[s][adr + 3], qpos[s][adr + 4], qpos[s][adr + 5], qpos[s][adr + 6]);
            const Vec4 mismatch = quaternion_product(Vec4(mj[0], -mj[1], -mj[2], -mj[3]), e.normalized());
            worst = std::max(worst, 2.0 * std::asin(std::min(1.0, mismatch.tail<3>().norm())));
        }
        ++compared;
    }
    EXPECT_EQ(compared, m->njnt) << "every MuJoCo joint compared";
    return worst;
}

}  // namespace mbd::test
