// The cross-formulation harness: every dynamics scene in scenes/dynamics/ is run with
// every formulation the plugin registry finds (the single list: a new formulation plugin
// joins automatically) and compared with the augmented formulation (book Eq. 6.141), the
// reference: the same positions and joint reactions (reactions.hpp) at the end time,
// to within 100 x the integration tolerance (relative to the size of the quantity).
#include <mbd/model_system.hpp>
#include <mbd/sdk/reactions.hpp>
#include <mbd/simulation.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "support/test_support.hpp"

namespace {

using mbd::test::position_difference;

using mbd::test::shared_registry;

constexpr double kTolerance = 1e-10;
constexpr double kEndTime = 0.5;
const char* kReference = "augmented";

std::vector<std::string> dynamics_scenes() {
    std::vector<std::string> out;
    for (const auto& entry : std::filesystem::directory_iterator(mbd::test::scene_path("dynamics")))
        if (entry.path().extension() == ".yaml") out.push_back(entry.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
}

// every formulation plugin found, the reference first
std::vector<std::string> formulations() {
    std::vector<std::string> names = shared_registry().type_names("formulation");
    std::stable_partition(names.begin(), names.end(), [](const std::string& n) { return n == kReference; });
    return names;
}

struct End {
    mbd::State state;
    std::vector<mbd::JointReaction> reactions;
};

End run(const mbd::Model& model, const std::string& formulation) {
    mbd::SimulationSettings s;
    s.formulation = formulation;
    s.integrator = "dopri5";
    s.integration.tolerance = kTolerance;
    s.t_end = kEndTime;
    s.output_step = kEndTime;
    s.reactions = true;
    s.progress = false;
    End end;
    Eigen::VectorXd lambda;
    mbd::simulate(model, shared_registry(), s, [&](const mbd::SimulationSample& sample) {
        end.state = sample.state;
        if (sample.lambda) lambda = *sample.lambda;
        return true;
    });
    mbd::ModelSystem system(model);
    end.reactions = mbd::joint_reactions(system, end.state, lambda);
    return end;
}

class CrossFormulation : public ::testing::TestWithParam<std::string> {};

TEST_P(CrossFormulation, EveryFormulationMatchesTheReference) {
    const std::string scene = GetParam();
    const mbd::Model model = mbd::load_scene(mbd::test::scene_path("dynamics/" + scene).string(), shared_registry());
    const std::vector<std::string> names = formulations();
    ASSERT_FALSE(names.empty());
    ASSERT_EQ(names.front(), kReference);
    const End reference = run(model, kReference);
    double q_scale = 1.0, r_scale = 1.0;
    q_scale = std::max(q_scale, reference.state.q.lpNorm<Eigen::Infinity>());
    for (const auto& r : reference.reactions)
        for (const auto& on : r.on) r_scale = std::max({r_scale, on.force.norm(), on.torque.norm()});
    for (size_t k = 1; k < names.size(); ++k) {
        const End other = run(model, names[k]);
        const double dq = position_difference(model, other.state.q, reference.state.q);
        double dr = 0.0;
        ASSERT_EQ(other.reactions.size(), reference.reactions.size());
        for (size_t j = 0; j < other.reactions.size(); ++j)
            for (size_t b = 0; b < other.reactions[j].on.size(); ++b) {
                dr = std::max(dr, (other.reactions[j].on[b].force - reference.reactions[j].on[b].force).norm());
                dr = std::max(dr, (other.reactions[j].on[b].torque - reference.reactions[j].on[b].torque).norm());
            }
        std::printf("%-32s %-12s vs %s at t = %g: |dq| %.3e (scale %.3g), |dreaction| %.3e (scale %.3g)\n",
                    scene.c_str(), names[k].c_str(), kReference, kEndTime, dq, q_scale, dr, r_scale);
        EXPECT_LT(dq, 100 * kTolerance * q_scale) << names[k] << " positions on " << scene;
        EXPECT_LT(dr, 100 * kTolerance * r_scale) << names[k] << " reactions on " << scene;
    }
}

INSTANTIATE_TEST_SUITE_P(DynamicsScenes, CrossFormulation, ::testing::ValuesIn(dynamics_scenes()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                             std::string name = info.param.substr(0, info.param.size() - 5);
                             for (char& c : name)
                                 if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                             return name;
                         });

}  // namespace
