// Statics with redundant constraint rows (issue 42): the equilibrium determines the constraint
// forces J^T lambda, not the multipliers, so the reactions of the joints a self-stress loads are
// not determined. scenes/statics/toggle-straight.yaml: two 1 m links in a line between a ground
// pin A and a slider C on a guide across the line, pulled along the line by P = 100 N. Every
// split of P between the links' tension t (A, B and C carry t along x) and the guide (P - t) is
// an equilibrium; the reactions must be reported as not determined, with the redundant row
// named as `mbd check` names it, and the values shown must be the minimum-norm ones, not the
// solver's (issue 42's toggle: a 4.3e5 N self-stress left by its iterations).
#include "support/test_support.hpp"

#include <mbd/model_system.hpp>
#include <mbd/statics_analysis.hpp>

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <string>

namespace {

using mbd::test::run_mbd;
using mbd::test::scene_path;

bool contains(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

const std::string kToggle = "statics/toggle-straight.yaml";

TEST(StaticsRedundancy, MinimumNormMultipliersKeepTheConstraintForces) {
    const mbd::Model model = mbd::test::load(kToggle);
    mbd::ModelSystem system(model);
    mbd::State state = system.initial_state();
    state.v.setZero(system.nv());
    mbd::ConstraintValues cv;
    system.constraints(state, cv, true);
    const Eigen::MatrixXd J(cv.J);
    // a self-stress (a null vector of J^T, independent of the code under test: the full SVD)
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(J.transpose(), Eigen::ComputeFullV);
    ASSERT_EQ(svd.rank(), J.rows() - 1);
    const Eigen::VectorXd stress = svd.matrixV().col(J.rows() - 1);
    EXPECT_LT((J.transpose() * stress).norm(), 1e-12);
    // multipliers with the constraint forces of a particular solution plus 4e5 of that stress
    const Eigen::VectorXd particular = Eigen::VectorXd::LinSpaced(J.rows(), 1.0, 2.0);
    Eigen::VectorXd lambda = particular + 4e5 * stress;
    const mbd::StaticIndeterminacy in = mbd::resolve_indeterminacy(model, system, state, lambda);
    ASSERT_TRUE(in.any());
    ASSERT_EQ(in.redundant_rows.size(), 1u);
    // the same J^T lambda, orthogonal to the stress: the minimum-norm member of the family
    EXPECT_LT((J.transpose() * (lambda - particular)).norm(), 1e-8);
    EXPECT_LT(std::abs(lambda.dot(stress)), 1e-8);
    EXPECT_NEAR(lambda.norm(), (particular - particular.dot(stress) * stress).norm(), 1e-9);
    // every joint carries the stress (the links' tension along the line, the guide's push)
    for (const char* joint : {"A", "B", "C", "guide"})
        EXPECT_NE(std::find(in.undetermined_joints.begin(), in.undetermined_joints.end(), joint),
                  in.undetermined_joints.end())
            << joint;
}

TEST(StaticsRedundancy, StraightToggleNamesTheRedundancyAndNoDeterminedReactions) {
    const auto check = run_mbd("check " + scene_path(kToggle).string());
    ASSERT_EQ(check.exit_code, 0) << check.err;
    ASSERT_TRUE(contains(check.out, "redundant constraint rows (1):")) << check.out;
    const std::string row = check.out.substr(check.out.find("redundant constraint rows (1):\n  ") + 33);
    const std::string named = row.substr(0, row.find('\n'));  // e.g. "joint 'guide' (row ...)"

    const auto statics = run_mbd("statics " + scene_path(kToggle).string());
    ASSERT_EQ(statics.exit_code, 0) << statics.err;
    EXPECT_TRUE(contains(statics.out, "reactions NOT DETERMINED: 1 redundant constraint row")) << statics.out;
    EXPECT_TRUE(contains(statics.out, "  " + named + "\n")) << named << "\n" << statics.out;
    EXPECT_TRUE(contains(statics.out, "minimum-norm")) << statics.out;
    EXPECT_TRUE(contains(statics.out, "\n* A ")) << statics.out;
    EXPECT_TRUE(contains(statics.out, "\n* guide ")) << statics.out;

    const auto json = run_mbd("statics " + scene_path(kToggle).string() + " --json");
    ASSERT_EQ(json.exit_code, 0) << json.err;
    EXPECT_TRUE(contains(json.out, "\"reactions_determined\":false")) << json.out;
    EXPECT_TRUE(contains(json.out, "\"redundant_rows\":[\"" + named.substr(0, named.find('\'')))) << json.out;

    // the reactions shown: each an equilibrium (P = 100 N shared by the links' tension t and
    // the guide), with the self-stress the smallest the multipliers allow, not 4e5 N
    const mbd::Model model = mbd::test::load(kToggle);
    mbd::StaticsOptions options;
    const mbd::StaticsReport report = mbd::run_statics(model, mbd::test::shared_registry(), options);
    ASSERT_TRUE(report.result.converged) << report.result.message;
    ASSERT_TRUE(report.indeterminacy.any());
    ASSERT_EQ(report.reactions.size(), 4u);
    const double t = -report.reactions[0].force.x();  // A's reaction on link1 (second body), world x
    for (const mbd::JointLoad& l : report.reactions) {
        std::printf("%-6s F = [%.6g, %.6g]  T = %.6g\n", l.name.c_str(), l.force.x(), l.force.y(), l.torque.z());
        EXPECT_LT(l.force.norm(), 100.0 + 1e-6) << l.name;
        EXPECT_NEAR(l.force.y(), 0.0, 1e-6) << l.name;
    }
    std::printf("links' tension %.9g N, guide %.9g N\n", t, report.reactions[3].force.x());
    // the minimum norm: each row's multiplier is the force along it (unit rows), so the family
    // (t, t, t, P - t) along x is smallest at 3 t = P - t: t = P / 4
    EXPECT_NEAR(t, 25.0, 1e-6);
    EXPECT_NEAR(-report.reactions[3].force.x(), 75.0, 1e-6);
}

}  // namespace
