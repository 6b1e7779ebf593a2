// Issue 37: DART (Debian libdart-utils-urdf-dev, its own URDF reader) and mbd run the same URDF
// robot from ../shared/models. DART's World steps with semi-implicit Euler, a first-order method,
// so 1e-6 over 1 s would need ~1e7 steps; the test shows instead that DART converges to mbd's
// trajectory at order 1 (the difference halves with the step) and that the Richardson
// extrapolation of three DART runs agrees with mbd to 1e-6 (docs/import.md).
#include "support/mujoco_oracle.hpp"  // shared_models()
#include "support/test_support.hpp"

#include <mbd/import/import.hpp>
#include <mbd/import/scene_writer.hpp>

#include <dart/dynamics/BodyNode.hpp>
#include <dart/dynamics/DegreeOfFreedom.hpp>
#include <dart/dynamics/Joint.hpp>
#include <dart/dynamics/Skeleton.hpp>
#include <dart/simulation/World.hpp>
#include <dart/utils/urdf/DartLoader.hpp>

#include <gtest/gtest.h>

#include <fstream>
#include <regex>

namespace mbd::test {
namespace {

namespace fs = std::filesystem;

// The documented initial state: revolute joint number k (the file's order of DART's degrees of
// freedom, from 0) turns at (-1)^k (1 + 0.1 k) rad/s from the file's reference configuration.
std::map<std::string, std::vector<double>> joint_rates(const dart::dynamics::SkeletonPtr& robot) {
    std::map<std::string, std::vector<double>> rates;
    for (size_t k = 0; k < robot->getNumDofs(); ++k)
        rates[robot->getDof(k)->getJoint()->getName()] = {(k % 2 ? -1.0 : 1.0) * (1.0 + 0.1 * k)};
    return rates;
}

// Every body's mass centre (world) at t = 1 s, by body name, from DART at step h.
std::map<std::string, Vec3> dart_run(const fs::path& urdf, double h) {
    dart::utils::DartLoader loader;
    dart::dynamics::SkeletonPtr robot = loader.parseSkeleton(dart::common::Uri::createFromPath(urdf.string()));
    EXPECT_TRUE(robot) << urdf;
    if (!robot) return {};
    auto world = dart::simulation::World::create();
    world->setGravity(Eigen::Vector3d(0, 0, -9.81));
    world->setTimeStep(h);
    world->addSkeleton(robot);
    for (const auto& [name, rate] : joint_rates(robot)) robot->getJoint(name)->setVelocity(0, rate[0]);
    const long steps = std::lround(1.0 / h);
    for (long k = 0; k < steps; ++k) world->step();
    std::map<std::string, Vec3> out;
    for (size_t b = 0; b < robot->getNumBodyNodes(); ++b)
        out[robot->getBodyNode(b)->getName()] = robot->getBodyNode(b)->getCOM();
    return out;
}

double largest_difference(const std::map<std::string, Vec3>& dart, const Model& model, const Eigen::VectorXd& q) {
    double worst = 0.0;
    int compared = 0;
    for (int b = 0; b < model.body_count(); ++b) {
        const auto it = dart.find(model.bodies[b].name);
        if (it == dart.end()) continue;
        worst = std::max(worst, (it->second - q.segment<3>(7 * b)).cwiseAbs().maxCoeff());
        ++compared;
    }
    EXPECT_EQ(compared, 6);  // the UR5's six moving links
    return worst;
}

TEST(DartAgreement, Ur5UrdfConvergesToMbdAtFirstOrder) {
    // DART reads a copy without <visual> and <collision>: its reader cannot resolve the
    // package:// meshes, missing on purpose; URDF inertias are explicit.
    const fs::path urdf = shared_models() / "erd_ur5" / "ur5_robot.urdf";
    const std::regex geometry("<visual>[\\s\\S]*?</visual>|<collision>[\\s\\S]*?</collision>");
    const fs::path copy = write_text(scratch("dart_ur5") / "ur5_robot.urdf", std::regex_replace(read_text(urdf), geometry, ""));
    dart::utils::DartLoader loader;
    const dart::dynamics::SkeletonPtr robot = loader.parseSkeleton(dart::common::Uri::createFromPath(copy.string()));
    ASSERT_TRUE(robot);
    ASSERT_EQ(robot->getNumDofs(), 6u);  // welded to the world, six revolute joints
    import::ImportOptions options;
    options.joint_velocities = joint_rates(robot);
    const import::ImportedScene imported = import::import_model(urdf, options);
    const Model model = scene(import::scene_yaml(imported), "ur5.yaml");
    const std::vector<Eigen::VectorXd> q = mbd_run(model, 1.0, 1.0);
    ASSERT_EQ(q.size(), 2u);
    std::vector<std::map<std::string, Vec3>> runs;
    const double steps[] = {4e-4, 2e-4, 1e-4};
    std::vector<double> errors;
    for (double h : steps) {
        runs.push_back(dart_run(copy, h));
        errors.push_back(largest_difference(runs.back(), model, q.back()));
    }
    // Richardson: each pair 2 x(h/2) - x(h) removes DART's first-order error term; the two pairs
    // combined, (4 R(h/2) - R(h)) / 3, its second-order term too.
    auto combined = [](double a, const std::map<std::string, Vec3>& x, double b, const std::map<std::string, Vec3>& y) {
        std::map<std::string, Vec3> out;
        for (const auto& [name, p] : x) out[name] = a * p + b * y.at(name);
        return out;
    };
    const auto first_a = combined(2.0, runs[1], -1.0, runs[0]);
    const auto first_b = combined(2.0, runs[2], -1.0, runs[1]);
    const auto second = combined(4.0 / 3.0, first_b, -1.0 / 3.0, first_a);
    const double richardson1 = largest_difference(first_b, model, q.back());
    const double richardson2 = largest_difference(second, model, q.back());
    std::printf("DART (semi-implicit Euler) against mbd, every link's mass centre at t = 1 s: h = 4e-4 %.3e, "
                "2e-4 %.3e, 1e-4 %.3e (ratios %.3f, %.3f); extrapolated once %.3e, twice %.3e\n",
                errors[0], errors[1], errors[2], errors[0] / errors[1], errors[1] / errors[2], richardson1, richardson2);
    for (int k = 0; k < 2; ++k) {  // order 1: the difference halves with the step
        EXPECT_GT(errors[k] / errors[k + 1], 1.9);
        EXPECT_LT(errors[k] / errors[k + 1], 2.1);
    }
    EXPECT_LT(richardson1, errors[2] / 100);
    EXPECT_LT(richardson2, 1e-6);
}

}  // namespace
}  // namespace mbd::test
