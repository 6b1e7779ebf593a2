// The amalgamated formulation (book Sec. 4.6, Eq. 4.20): its accelerations and multipliers
// against the augmented formulation (Eq. 6.141, a different linear system) at random
// consistent states; the Newton-Euler balance with its reactions; drift with projection;
// and switching between the four formulations from the command line.
#include <mbd/model_system.hpp>
#include <mbd/simulation.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

#include "support/test_support.hpp"

namespace {

using mbd::test::load;
using mbd::test::make_formulation;
using mbd::test::random_consistent_state;
using mbd::test::scratch;

namespace fs = std::filesystem;
using mbd::test::run_mbd;
using mbd::test::shared_registry;

class AmalgamatedVsAugmented : public ::testing::TestWithParam<std::string> {};

TEST_P(AmalgamatedVsAugmented, AccelerationsAndMultipliersAtRandomConsistentStates) {
    const mbd::Model model = load(GetParam());
    mbd::ModelSystem system(model);
    mbd::Param n1, n2;
    auto amalgamated = make_formulation("amalgamated", n1);
    auto augmented = make_formulation("augmented", n2);
    amalgamated->bind(system, {});
    augmented->bind(system, {});
    std::mt19937 rng(12345);
    double worst = 0.0, worst_lambda = 0.0, worst_balance = 0.0;
    for (int trial = 0; trial < 20; ++trial) {
        const mbd::State s = random_consistent_state(system, rng, 0.2);
        Eigen::VectorXd a1, a2, l1, l2, Q;
        amalgamated->accelerations(s, a1);
        augmented->accelerations(s, a2);
        amalgamated->multipliers(s, l1);
        augmented->multipliers(s, l2);
        const double scale = std::max(1.0, a2.lpNorm<Eigen::Infinity>());
        worst = std::max(worst, (a1 - a2).lpNorm<Eigen::Infinity>() / scale);
        if (l2.size())
            worst_lambda = std::max(worst_lambda, (l1 - l2).lpNorm<Eigen::Infinity>() / std::max(1.0, l2.lpNorm<Eigen::Infinity>()));
        // Newton-Euler with the reactions: M vdot = Q - J^T lambda (Eqs. 4.17, 6.128)
        system.generalized_forces(s, Q);
        mbd::ConstraintValues cv;
        system.constraints(s, cv, true);
        Eigen::VectorXd residual = system.mass_matrix() * a1 - Q;
        if (l1.size()) residual += cv.J.transpose() * l1;
        worst_balance = std::max(worst_balance, residual.lpNorm<Eigen::Infinity>() /
                                                    std::max(1.0, Q.lpNorm<Eigen::Infinity>()));
    }
    std::printf("%-40s |vdot_amalgamated - vdot_augmented| / scale = %.2e, multipliers %.2e, balance %.2e\n",
                GetParam().c_str(), worst, worst_lambda, worst_balance);
    EXPECT_LT(worst, 1e-10);
    EXPECT_LT(worst_lambda, 1e-9);
    EXPECT_LT(worst_balance, 1e-10);
}

INSTANTIATE_TEST_SUITE_P(Scenes, AmalgamatedVsAugmented,
                         ::testing::Values("dynamics/four-bar-conservative.yaml", "dynamics/four-bar-spring-damper.yaml",
                                           "dynamics/slider-crank.yaml", "dynamics/rssr-gravity.yaml",
                                           "dynamics/heavy-top.yaml", "dynamics/pendulum-a01.yaml",
                                           "dynamics/torque-free-body.yaml"),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                             std::string name = fs::path(info.param).stem().string();
                             for (char& c : name)
                                 if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                             return name;
                         });

TEST(Amalgamated, ProjectionKeepsTheLoopClosed) {
    const mbd::Model model = load("dynamics/rssr-gravity.yaml");
    mbd::SimulationSettings s;
    s.formulation = "amalgamated";
    s.integration.tolerance = 1e-8;
    s.t_end = 2.0;
    s.progress = false;
    const mbd::SimulationResult r = mbd::simulate(model, shared_registry(), s);
    std::printf("rssr-gravity amalgamated 2 s: max |C| %.2e, max |J v + C_t| %.2e\n", r.final_position_violation,
                r.final_velocity_violation);
    EXPECT_LT(r.final_position_violation, 1e-10);
    EXPECT_LT(r.final_velocity_violation, 1e-9);
}

// ---- the command line: the same scene with each of the four formulations

std::vector<double> last_row(const fs::path& csv, std::vector<std::string>& header) {
    std::ifstream in(csv);
    std::string line, last;
    std::getline(in, line);
    header.clear();
    {
        std::stringstream s(line);
        std::string cell;
        while (std::getline(s, cell, ',')) header.push_back(cell);
    }
    while (std::getline(in, line))
        if (!line.empty()) last = line;
    std::vector<double> row;
    std::stringstream s(last);
    std::string cell;
    while (std::getline(s, cell, ',')) row.push_back(std::stod(cell));
    return row;
}

const char* kFour[] = {"augmented", "embedding", "amalgamated", "hamiltonian"};

TEST(FourFormulationsCli, SwitchingIsOnlyTheFormulationOption) {
    const fs::path dir = scratch("four");
    const std::string scene = mbd::test::scene_path("dynamics/four-bar-spring-damper.yaml").string();
    std::vector<std::string> reference_header;
    std::vector<double> reference;
    for (const char* name : kFour) {
        const fs::path out = dir / (std::string(name) + ".csv");
        const auto r = run_mbd("simulate " + scene + " --formulation " + name +
                               " --tol 1e-10 --t-end 1 --output-step 0.1 --reactions -q -o " + out.string());
        ASSERT_EQ(r.exit_code, 0) << name << ": " << r.err;
        std::vector<std::string> header;
        const std::vector<double> row = last_row(out, header);
        if (reference.empty()) {
            reference = row;
            reference_header = header;
            continue;
        }
        ASSERT_EQ(header, reference_header) << name;
        ASSERT_EQ(row.size(), reference.size()) << name;
        double worst = 0.0;
        for (size_t k = 0; k < row.size(); ++k)
            worst = std::max(worst, std::abs(row[k] - reference[k]) / std::max(1.0, std::abs(reference[k])));
        std::printf("four-bar-spring-damper t = 1: %-12s vs augmented, largest relative difference of the final row %.2e\n",
                    name, worst);
        EXPECT_LT(worst, 1e-7) << name;
    }
}

TEST(FourFormulationsCli, UnknownFormulationListsAllFour) {
    const fs::path dir = scratch("unknown");
    const auto r = run_mbd("simulate " + mbd::test::scene_path("dynamics/pendulum-a01.yaml").string() +
                           " --formulation lagrangian_magic --t-end 1 -o " + (dir / "x.csv").string());
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find("lagrangian_magic"), std::string::npos) << r.err;
    for (const char* name : kFour) EXPECT_NE(r.err.find(name), std::string::npos) << name << " not listed: " << r.err;
    EXPECT_FALSE(fs::exists(dir / "x.csv"));
}

}  // namespace
