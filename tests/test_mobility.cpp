// Mobility: Gruebler count against the rank of C_q, and the redundant rows of an
// overconstrained loop (the orthogonal Bricard linkage). Expected counts follow
// from the mechanisms' topology (book Sec. 3.1, Ex. 3.1, Ex. 3.2) and, for the
// Bricard linkage, from its six joint screws (a 1-dimensional null space).
#include <mbd/kinematics.hpp>
#include <mbd/mobility.hpp>
#include <mbd/registry.hpp>
#include <mbd/scene.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "support/test_support.hpp"

namespace {

mbd::Registry& registry() {
    static mbd::Registry instance({std::filesystem::path(MBD_BUILD_DIR) / "lib/mbd/plugins"});
    return instance;
}

std::filesystem::path book_scene(const std::string& name) {
    return std::filesystem::path(MBD_SOURCE_DIR) / "scenes/book" / name;
}

using mbd::test::read_text;

mbd::MobilityReport mobility_of(const std::string& scene) {
    const mbd::Model model = mbd::load_scene(book_scene(scene), registry());
    return mbd::analyse_mobility(model, model.initial_state());
}

TEST(Mobility, SliderCrankHasOneDegreeOfFreedom) {
    // Ex. 3.1 (in absolute coordinates without the ground body): 3 bodies x 3 = 9,
    // 3 revolute x 2 + 1 prismatic x 2 = 8 equations -> 1 DOF
    const mbd::MobilityReport r = mobility_of("slider-crank.yaml");
    EXPECT_EQ(r.coordinates, 9);
    EXPECT_EQ(r.constraint_rows, 8);
    EXPECT_EQ(r.driver_rows, 1);
    EXPECT_EQ(r.gruebler_dof, 1);
    EXPECT_EQ(r.rank, 8);
    EXPECT_EQ(r.rank_dof, 1);
    EXPECT_TRUE(r.redundant.empty());
}

TEST(Mobility, FourBarsHaveOneDegreeOfFreedom) {
    for (const char* scene : {"four-bar-table32.yaml", "four-bar-ex313.yaml"}) {
        const mbd::MobilityReport r = mobility_of(scene);
        EXPECT_EQ(r.coordinates, 9) << scene;
        EXPECT_EQ(r.constraint_rows, 8) << scene;
        EXPECT_EQ(r.gruebler_dof, 1) << scene;
        EXPECT_EQ(r.rank_dof, 1) << scene;
        EXPECT_TRUE(r.redundant.empty()) << scene;
    }
}

TEST(Mobility, RssrHasTheCrankAndTheCouplerSpin) {
    // Ex. 3.2: n_d = 24 - 22 = 2 with the ground's 6 coordinates; here 18 - 16 = 2
    const mbd::MobilityReport r = mobility_of("rssr.yaml");
    EXPECT_EQ(r.coordinates, 18);
    EXPECT_EQ(r.constraint_rows, 16);
    EXPECT_EQ(r.gruebler_dof, 2);
    EXPECT_EQ(r.rank_dof, 2);
    EXPECT_TRUE(r.redundant.empty());
}

TEST(Mobility, BricardIsMobileDespiteAZeroGrueblerCount) {
    const mbd::MobilityReport r = mobility_of("bricard.yaml");
    EXPECT_EQ(r.coordinates, 30);
    EXPECT_EQ(r.constraint_rows, 30);
    EXPECT_EQ(r.gruebler_dof, 0);
    EXPECT_EQ(r.rank, 29);
    EXPECT_EQ(r.rank_dof, 1);
    ASSERT_EQ(r.redundant.size(), 1u);
    EXPECT_EQ(r.redundant[0].kind, mbd::RowOwner::Kind::Joint);
    EXPECT_FALSE(r.redundant[0].element_name.empty());
    EXPECT_NE(r.redundant[0].describe().find("joint '"), std::string::npos) << r.redundant[0].describe();
}

TEST(Mobility, BricardMovesAlongItsOneDegreeOfFreedom) {
    // Drive the first joint: the redundant loop still assembles at every step
    // (the min-norm solves accept consistent redundant rows) and stays 1-DOF.
    std::string yaml = read_text(book_scene("bricard.yaml"));
    yaml += "drivers:\n  - {name: motor, joint: J0, motion: {type: linear, initial: 0.0, rate: 1.0}}\n";
    const mbd::Model model = mbd::load_scene_text(yaml, "bricard-driven.yaml", registry());
    int samples = 0;
    mbd::State last;
    mbd::run_kinematics(model, 0.5, 0.05, [&](const mbd::State& s, const Eigen::VectorXd&) {
        ++samples;
        last = s;
        return true;
    });
    EXPECT_EQ(samples, 11);
    const mbd::ConstraintSystem joints(model, false);
    mbd::ConstraintValues values;
    mbd::Data data(model);
    joints.evaluate(last, data, values);
    EXPECT_LE(values.C.cwiseAbs().maxCoeff(), 1e-9);
    // bar1 turned about world y by 0.5 rad about C0: its centre moved from (0.5, 0, 0)
    const Eigen::Vector3d R1 = last.q.segment<3>(model.q_offset(model.body_index("bar1")));
    EXPECT_NEAR(R1.x(), 0.5 * std::cos(0.5), 1e-9);
    EXPECT_NEAR(R1.y(), 0.0, 1e-9);
    EXPECT_NEAR(R1.z(), -0.5 * std::sin(0.5), 1e-9);
    const mbd::MobilityReport r = mbd::analyse_mobility(model, last);
    EXPECT_EQ(r.rank_dof, 1);
    EXPECT_EQ(r.redundant.size(), 1u);
}

// ------------------------------------------------------------------ via the CLI

TEST(MobilityCli, CheckPrintsBothCounts) {
    const auto bricard = mbd::test::run_mbd("check " + book_scene("bricard.yaml").string());
    ASSERT_EQ(bricard.exit_code, 0) << bricard.err;
    EXPECT_NE(bricard.out.find("degrees of freedom (Gruebler count): 0\n"), std::string::npos) << bricard.out;
    EXPECT_NE(bricard.out.find("degrees of freedom (rank of C_q): 1 "), std::string::npos) << bricard.out;
    EXPECT_NE(bricard.out.find("redundant constraint rows (1):"), std::string::npos) << bricard.out;
    EXPECT_NE(bricard.out.find("kinematically driven: no"), std::string::npos) << bricard.out;

    for (const char* scene : {"slider-crank.yaml", "four-bar-table32.yaml"}) {
        const auto r = mbd::test::run_mbd(std::string("check ") + book_scene(scene).string());
        ASSERT_EQ(r.exit_code, 0) << scene << ": " << r.err;
        EXPECT_NE(r.out.find("degrees of freedom (Gruebler count): 1\n"), std::string::npos) << r.out;
        EXPECT_NE(r.out.find("degrees of freedom (rank of C_q): 1 "), std::string::npos) << r.out;
        EXPECT_EQ(r.out.find("redundant constraint rows"), std::string::npos) << r.out;
        EXPECT_NE(r.out.find("kinematically driven: yes"), std::string::npos) << r.out;
    }

    const auto rssr = mbd::test::run_mbd("check " + book_scene("rssr.yaml").string());
    ASSERT_EQ(rssr.exit_code, 0) << rssr.err;
    EXPECT_NE(rssr.out.find("degrees of freedom (Gruebler count): 2\n"), std::string::npos) << rssr.out;
    EXPECT_NE(rssr.out.find("kinematically driven: no (1 degree of freedom left free"), std::string::npos) << rssr.out;
}

}  // namespace
