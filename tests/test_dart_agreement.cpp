// Issue 37: DART (Debian libdart-utils-urdf-dev, its own URDF reader and its own multibody
// dynamics) and mbd run the same URDF robot from ../shared/models. DART's World steps with
// semi-implicit Euler (first order: 1e-6 over 1 s would need ~1e7 steps), so the test integrates
// DART's dynamics itself: the skeleton's positions and velocities set, computeForwardDynamics()
// gives the accelerations, classical RK4 at a step whose own error (step halving) is below 1e-9
// integrates them. Every joint coordinate agrees with mbd's run of the file to 1e-6 over 1 s,
// every 0.01 s (docs/import.md).
#include "support/mujoco_oracle.hpp"  // shared_models(), urdf_without_geometry, mbd_run, scene_joint_travel
#include "support/test_support.hpp"

#include <mbd/import/import.hpp>
#include <mbd/import/scene_writer.hpp>

#include <dart/dynamics/DegreeOfFreedom.hpp>
#include <dart/dynamics/Joint.hpp>
#include <dart/dynamics/PrismaticJoint.hpp>
#include <dart/dynamics/RevoluteJoint.hpp>
#include <dart/dynamics/Skeleton.hpp>
#include <dart/utils/urdf/DartLoader.hpp>

#include <gtest/gtest.h>

#include <cstdio>
#include <limits>

namespace mbd::test {
namespace {

namespace fs = std::filesystem;

// RK4 steps at which DART's h and h / 2 runs differ by less than 1e-9 (order 4: the difference
// falls by 16 per halving; measured at 2e-3, 1e-3, 5e-4)
constexpr double kUr5Step = 5e-4, kPandaStep = 2.5e-4, kDoublePendulumStep = 2e-4;

// The documented initial state: revolute joint number k (the file's order of DART's revolute
// degrees of freedom, from 0) turns at (-1)^k (1 + 0.1 k) rad/s from the file's reference
// configuration; prismatic joints start at rest.
std::map<std::string, std::vector<double>> joint_rates(const dart::dynamics::SkeletonPtr& robot) {
    std::map<std::string, std::vector<double>> rates;
    size_t revolute = 0;
    for (size_t k = 0; k < robot->getNumDofs(); ++k) {
        const dart::dynamics::Joint* joint = robot->getDof(k)->getJoint();
        const bool turns = joint->getType() == dart::dynamics::RevoluteJoint::getStaticType();
        rates[joint->getName()] = {turns ? (revolute % 2 ? -1.0 : 1.0) * (1.0 + 0.1 * revolute) : 0.0};
        revolute += turns;
    }
    return rates;
}

// The URDF as DART reads it, with what the comparison leaves out switched off: a root link
// without a joint welded to the world (as urdfdom's and MuJoCo's readers weld it), no limits
// (DART's constraint solver would enforce them), damping, friction or springs, and a <mimic>
// joint a plain joint (DART's mimic is a servo of the leader's velocity).
dart::dynamics::SkeletonPtr dart_robot(const fs::path& urdf) {
    dart::utils::DartLoader::Options options;
    options.mDefaultRootJointType = dart::utils::DartLoader::RootJointType::FIXED;
    dart::utils::DartLoader loader(options);
    dart::dynamics::SkeletonPtr robot = loader.parseSkeleton(dart::common::Uri::createFromPath(urdf.string()));
    EXPECT_TRUE(robot) << urdf;
    if (!robot) return robot;
    for (size_t j = 0; j < robot->getNumJoints(); ++j) {
        dart::dynamics::Joint* joint = robot->getJoint(j);
        joint->setLimitEnforcement(false);
        joint->setActuatorType(dart::dynamics::Joint::FORCE);
        for (size_t k = 0; k < joint->getNumDofs(); ++k) {
            joint->setDampingCoefficient(k, 0.0);
            joint->setCoulombFriction(k, 0.0);
            joint->setSpringStiffness(k, 0.0);
            const double inf = std::numeric_limits<double>::infinity();
            joint->setPositionLowerLimit(k, -inf), joint->setPositionUpperLimit(k, inf);
            joint->setVelocityLowerLimit(k, -inf), joint->setVelocityUpperLimit(k, inf);
            joint->setForceLowerLimit(k, -inf), joint->setForceUpperLimit(k, inf);
        }
    }
    robot->setPositions(Eigen::VectorXd::Zero(robot->getNumDofs()));  // DART starts a joint at 0 only inside its limits
    return robot;
}

// DART's joint positions every `sample` s over [0, t_end] from zero positions and the velocities
// v0: its forward dynamics (articulated-body algorithm) integrated by classical RK4 at step h.
std::vector<Eigen::VectorXd> dart_rk4(const dart::dynamics::SkeletonPtr& robot, const Eigen::VectorXd& v0, double h,
                                      double t_end, double sample) {
    const Eigen::Index n = static_cast<Eigen::Index>(robot->getNumDofs());
    auto rate = [&](const Eigen::VectorXd& y) {  // y = (q, v) -> (v, vdot)
        robot->setPositions(y.head(n));
        robot->setVelocities(y.tail(n));
        robot->computeForwardDynamics();
        Eigen::VectorXd ydot(2 * n);
        ydot << y.tail(n), robot->getAccelerations();
        return ydot;
    };
    Eigen::VectorXd y(2 * n);
    y << Eigen::VectorXd::Zero(n), v0;
    std::vector<Eigen::VectorXd> out{y.head(n)};
    const long per_sample = std::lround(sample / h), samples = std::lround(t_end / sample);
    for (long s = 0; s < samples; ++s) {
        for (long k = 0; k < per_sample; ++k) {
            const Eigen::VectorXd k1 = rate(y), k2 = rate(y + 0.5 * h * k1), k3 = rate(y + 0.5 * h * k2), k4 = rate(y + h * k3);
            y += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        }
        out.push_back(y.head(n));
    }
    return out;
}

struct DartAgreementResult {
    double dart_self = 0.0;  // DART RK4 at h against h / 2, every joint coordinate
    double mbd = 0.0;        // mbd against DART at h / 2
    int compared = 0;        // joints compared
};

// The URDF `urdf` run by mbd (the file itself) and by DART (a copy without geometry,
// urdf_without_geometry) over 1 s from zero joint positions with the documented rates
// (joint_rates), compared in every joint coordinate every 0.01 s.
DartAgreementResult dart_agreement(const fs::path& urdf, const std::string& folder, size_t dofs, double h) {
    const dart::dynamics::SkeletonPtr robot = dart_robot(urdf_without_geometry(urdf, folder));
    if (!robot) return {1.0, 1.0, 0};
    EXPECT_EQ(robot->getNumDofs(), dofs) << urdf;
    robot->setGravity(Eigen::Vector3d(0, 0, -9.81));
    import::ImportOptions options;
    options.joint_velocities = joint_rates(robot);
    Eigen::VectorXd v0(robot->getNumDofs());
    for (size_t k = 0; k < robot->getNumDofs(); ++k) v0[k] = options.joint_velocities.at(robot->getDof(k)->getJoint()->getName())[0];
    import::SourceTree tree = import::read_model_file(urdf);
    conservative_source_tree(tree);
    import::apply_joint_velocities(tree, options);
    const import::ImportedScene imported = import::build_scene(tree);
    const Model model = scene(import::scene_yaml(imported), urdf.filename().string() + ".yaml");
    const std::vector<Eigen::VectorXd> q = mbd_run(model, 1.0, 0.01);
    const std::vector<Eigen::VectorXd> coarse = dart_rk4(robot, v0, h, 1.0, 0.01), fine = dart_rk4(robot, v0, h / 2, 1.0, 0.01);
    DartAgreementResult out;
    EXPECT_EQ(q.size(), fine.size());
    for (size_t s = 0; s < coarse.size() && s < fine.size(); ++s)
        out.dart_self = std::max(out.dart_self, (coarse[s] - fine[s]).lpNorm<Eigen::Infinity>());
    for (const import::SceneJoint& joint : imported.joints) {
        const dart::dynamics::Joint* dart_joint = robot->getJoint(joint.name);
        EXPECT_TRUE(dart_joint) << joint.name;
        if (!dart_joint) continue;
        const bool slide = dart_joint->getType() == dart::dynamics::PrismaticJoint::getStaticType();
        EXPECT_TRUE(slide || dart_joint->getType() == dart::dynamics::RevoluteJoint::getStaticType()) << joint.name;
        const size_t k = dart_joint->getDof(0)->getIndexInSkeleton();
        for (size_t s = 0; s < q.size() && s < fine.size(); ++s) {
            const double gap = scene_joint_travel(joint, slide, imported, model, q[0], q[s]) - fine[s][k];
            out.mbd = std::max(out.mbd, std::abs(slide ? gap : wrap_angle(gap)));
        }
        ++out.compared;
    }
    std::printf("%s: DART (its forward dynamics, RK4) at h = %g against h / 2: %.3g; mbd against DART over 1 s, "
                "%d joints: %.3g\n", urdf.filename().c_str(), h, out.dart_self, out.compared, out.mbd);
    return out;
}

void expect_agreement(const DartAgreementResult& a, int joints) {
    EXPECT_EQ(a.compared, joints);
    EXPECT_LT(a.dart_self, 1e-9);
    EXPECT_LT(a.mbd, 1e-6);
}

// Welded to the world by the file's own fixed joint, six revolute joints.
TEST(DartAgreement, Ur5UrdfAgreesWithDartToRk4Accuracy) {
    expect_agreement(dart_agreement(shared_models() / "erd_ur5" / "ur5_robot.urdf", "dart_ur5", 6, kUr5Step), 6);
}

// example-robot-data's panda: 7 revolute joints and two free prismatic fingers (the <mimic> left
// out on both sides: DART's mimic is a servo of the leader's velocity), panda_link8, panda_hand
// and panda_hand_tcp fused into panda_link7 by mbd. The fingers are flung out by the arm's turning.
TEST(DartAgreement, PandaUrdfAgreesWithDartToRk4Accuracy) {
    expect_agreement(dart_agreement(shared_models() / "erd_panda" / "panda.urdf", "dart_panda", 9, kPandaStep), 9);
}

// example-robot-data's double pendulum (off-diagonal inertias) started upright, falling and
// whipping under gravity, its limits (lower = upper = 0) and damping left out.
TEST(DartAgreement, DoublePendulumUrdfAgreesWithDartToRk4Accuracy) {
    expect_agreement(
        dart_agreement(shared_models() / "erd_double_pendulum" / "double_pendulum.urdf", "dart_double_pendulum", 2, kDoublePendulumStep), 2);
}

}  // namespace
}  // namespace mbd::test
