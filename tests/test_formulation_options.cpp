// A formulation's options reach it typed (formulation_setup.hpp): the scene's keys and the
// command line's choices give the same run; the command line wins over the scene; each
// option has the effect its equations say; and every wrong key is refused by name.
//
// Oracles: two routes to the same options must give bit-identical runs (the same
// arithmetic), and Baumgarte stabilization with alpha = beta = 0 adds exactly nothing to
// gamma (book Sec. 6.12: gamma - 2 alpha Cdot - beta^2 C), so it must equal no
// stabilization bit for bit.
#include <mbd/formulation_setup.hpp>
#include <mbd/scene.hpp>
#include <mbd/simulation.hpp>

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "support/test_support.hpp"

namespace {

using mbd::test::shared_registry;

// The four-bar of scenes/dynamics/four-bar-spring-damper.yaml with FORMULATION as its
// `formulation:` line.
mbd::Model four_bar(const std::string& formulation) {
    std::ifstream in(mbd::test::scene_path("dynamics/four-bar-spring-damper.yaml"));
    std::stringstream text;
    text << in.rdbuf() << "\nformulation: " << formulation << "\n";
    return mbd::load_scene_text(text.str(), "four-bar.yaml", shared_registry());
}

struct Outcome {
    mbd::SimulationResult result;
    std::vector<std::string> messages;
};

Outcome run(const mbd::Model& model, mbd::SimulationSettings settings = {}) {
    Outcome r;
    settings.t_end = 0.5;
    settings.integration.tolerance = 1e-5;
    if (settings.integrator.empty()) settings.integrator = "dopri5";  // the messages are the formulation's only
    settings.progress = false;
    settings.messages = mbd::MessageLog([&r](const std::string& line) { r.messages.push_back(line); });
    r.result = mbd::simulate(model, shared_registry(), settings);
    return r;
}

bool same_state(const mbd::State& a, const mbd::State& b) { return a.q == b.q && a.v == b.v; }

std::string load_error(const std::string& formulation) {
    try {
        run(four_bar(formulation));
    } catch (const mbd::InputError& e) {
        return e.what();
    }
    return "(no error)";
}

TEST(FormulationOptions, SceneKeysAndCommandLineGiveTheSameRun) {
    const Outcome scene = run(four_bar("{type: augmented, stabilization: none, linear_algebra: sparse}"));
    mbd::SimulationSettings cli;
    cli.stabilization = mbd::Stabilization::None;
    cli.algebra = mbd::LinearAlgebra::Sparse;
    const Outcome command_line = run(four_bar("augmented"), cli);
    EXPECT_TRUE(same_state(scene.result.final_state, command_line.result.final_state));

    // the option has its effect: without projection the loose run drifts off the constraints
    const Outcome projected = run(four_bar("augmented"));
    EXPECT_LT(projected.result.final_position_violation, 1e-10);
    EXPECT_GT(scene.result.final_position_violation, 100 * projected.result.final_position_violation);
}

TEST(FormulationOptions, CommandLineWinsOverTheScene) {
    mbd::SimulationSettings cli;
    cli.stabilization = mbd::Stabilization::Projection;
    const Outcome overridden = run(four_bar("{type: augmented, stabilization: none}"), cli);
    const Outcome scene = run(four_bar("{type: augmented, stabilization: projection}"));
    EXPECT_TRUE(same_state(overridden.result.final_state, scene.result.final_state));
}

TEST(FormulationOptions, BaumgarteGainsReachTheFormulation) {
    const Outcome zero_gains = run(four_bar("{type: augmented, stabilization: baumgarte, alpha: 0, beta: 0}"));
    const Outcome none = run(four_bar("{type: augmented, stabilization: none}"));
    const Outcome gains = run(four_bar("{type: augmented, stabilization: baumgarte, alpha: 20, beta: 20}"));
    EXPECT_TRUE(same_state(zero_gains.result.final_state, none.result.final_state));
    EXPECT_FALSE(same_state(gains.result.final_state, none.result.final_state));
    EXPECT_LT(gains.result.final_position_violation, none.result.final_position_violation);
}

TEST(FormulationOptions, SparseThresholdChoosesThePath) {
    // 9 velocity coordinates: a threshold of 5 puts auto on the sparse path
    const Outcome threshold = run(four_bar("{type: augmented, sparse_threshold: 5}"));
    const Outcome sparse = run(four_bar("{type: augmented, linear_algebra: sparse}"));
    const Outcome dense = run(four_bar("{type: augmented, linear_algebra: dense}"));
    EXPECT_TRUE(same_state(threshold.result.final_state, sparse.result.final_state));
    EXPECT_FALSE(same_state(threshold.result.final_state, dense.result.final_state));
}

TEST(FormulationOptions, LogChoosesTheMessages) {
    // the embedding reports its path unless `log: false`
    const Outcome quiet = run(four_bar("{type: embedding, log: false}"));
    const Outcome told = run(four_bar("embedding"));
    EXPECT_TRUE(quiet.messages.empty());
    ASSERT_FALSE(told.messages.empty());
    EXPECT_NE(told.messages.front().find("embedding: closure path"), std::string::npos) << told.messages.front();
    EXPECT_TRUE(same_state(quiet.result.final_state, told.result.final_state));
}

TEST(FormulationOptions, TheSceneKeysBelongToTheScenesFormulation) {
    // the command line runs another formulation: the scene's keys for augmented do not apply
    mbd::SimulationSettings cli;
    cli.formulation = "embedding";
    const Outcome r = run(four_bar("{type: augmented, linear_algebra: sparse, stabilization: none}"), cli);
    EXPECT_EQ(r.result.formulation, "embedding");
    EXPECT_LT(r.result.final_position_violation, 1e-9);
}

TEST(FormulationOptions, WrongKeysAreRefusedByName) {
    struct Case {
        std::string formulation;
        std::vector<std::string> parts;
    };
    const Case cases[] = {
        {"{type: augmented, stabilisation: none}",
         {"four-bar.yaml:", "formulation 'augmented': unknown key 'stabilisation'", "did you mean 'stabilization'",
          "Its keys are type, stabilization, alpha, beta, projection_tolerance, linear_algebra, sparse_threshold, "
          "singularity_tolerance"}},
        {"{type: embedding, stabilization: none}",
         {"unknown key 'stabilization' (the embedding formulation does not use it)", "path", "independent",
          "newton_iterations"}},
        {"{type: hamiltonian, linear_algebra: dense}", {"unknown key 'linear_algebra'", "does not use it"}},
        {"{type: amalgamated, warp: 2}", {"formulation 'amalgamated': unknown key 'warp'", "pivot_threshold"}},
        {"{type: augmented, stabilization: sometimes}",
         {"four-bar.yaml:", "'stabilization' must be projection, baumgarte or none, got 'sometimes'"}},
        {"{type: augmented, linear_algebra: fast}", {"'linear_algebra' must be auto, dense or sparse, got 'fast'"}},
        {"{type: embedding, log: maybe}", {"'log' must be true or false"}},
        {"{type: embedding, path: recursiv}", {"'path' must be auto, dense, recursive or closure, got 'recursiv'"}},
        {"{type: augmented, singularity_tolerance: 1}", {"'singularity_tolerance' must be in [0, 1)"}},
        {"{type: embedding, pivot_threshold: 2}", {"'pivot_threshold' must be in (0, 1]"}},
        {"{type: hamiltonian, newton_tolerance: -1}", {"'newton_tolerance' must be positive"}},
    };
    for (const Case& c : cases) {
        const std::string message = load_error(c.formulation);
        for (const std::string& part : c.parts) EXPECT_NE(message.find(part), std::string::npos) << message;
    }
}

}  // namespace
