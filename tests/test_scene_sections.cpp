// The Scene beside the physics-only Model (core scene.hpp): the core loader accepts the top-level
// keys an application declares (SceneSection) and hands them over unread; it names none itself,
// and every other unknown key is still refused at its file:line with the nearest key.
#include "support/test_support.hpp"

#include <mbd/app/bench.hpp>
#include <mbd/app/scene_sections.hpp>
#include <mbd/app/stability.hpp>
#include <mbd/scene.hpp>
#include <mbd/scene_parameters.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

namespace {

const std::string kPendulum =
    "dimension: planar\n"                                                   // line 1
    "gravity: [0, -9.81]\n"                                                 // 2
    "bodies:\n"                                                             // 3
    "  - {name: rod, mass: 2, inertia: 0.1, position: [0.5, 0]}\n"          // 4
    "joints:\n"                                                             // 5
    "  - {name: pin, type: revolute, bodies: [ground, rod], point: [0, 0]}\n";  // 6

std::string error_of(const std::string& yaml, const std::vector<mbd::SceneSection>& sections, std::string* where) {
    try {
        mbd::read_scene_text(yaml, "scene.yaml", mbd::test::shared_registry(), sections);
    } catch (const mbd::InputError& e) {
        *where = e.where();
        return e.message();
    }
    return "no error";
}

TEST(SceneSections, AnUnknownKeyIsRefusedAtItsLineWithTheNearestKey) {
    std::string where;
    const std::string message =
        error_of(kPendulum + "bech: {t_end: 1}\n", mbd::application_scene_sections(), &where);
    EXPECT_EQ(where, "scene.yaml:7");
    EXPECT_NE(message.find("unknown key 'bech' in scene; did you mean 'bench'?"), std::string::npos) << message;
    EXPECT_NE(message.find("is read by mbd bench"), std::string::npos) << message;
    // a physics key's misspelling is suggested as before
    const std::string gravity = error_of("gravty: [0, -1]\n" + kPendulum.substr(kPendulum.find("bodies")),
                                         mbd::application_scene_sections(), &where);
    EXPECT_EQ(where, "scene.yaml:1");
    EXPECT_NE(gravity.find("did you mean 'gravity'?"), std::string::npos) << gravity;
}

TEST(SceneSections, TheCoreAloneAcceptsNoApplicationKey) {
    // without the application's declaration `bench:` and `expect:` are unknown keys like any other
    for (const char* key : {"bench", "expect"}) {
        std::string where;
        const std::string message = error_of(kPendulum + key + ": {t_end: 1}\n", {}, &where);
        EXPECT_EQ(where, "scene.yaml:7") << key;
        EXPECT_NE(message.find("unknown key '" + std::string(key) + "' in scene"), std::string::npos) << message;
    }
}

TEST(SceneSections, ADeclaredKeyIsAcceptedAndReachesTheApplicationUnread) {
    const std::vector<mbd::SceneSection> sections = {{"my_tool", "a test"}};
    const mbd::Scene scene = mbd::read_scene_text(kPendulum + "my_tool:\n  speed: 3\n  mode: [a, b]\n", "scene.yaml",
                                                  mbd::test::shared_registry(), sections);
    const mbd::Param* tool = scene.section("my_tool");
    ASSERT_NE(tool, nullptr);
    ASSERT_TRUE(tool->is_map());
    EXPECT_EQ(tool->fields.at("speed").text, "3");
    EXPECT_EQ(tool->fields.at("speed").line, 8);  // its own file:line, for the application's messages
    EXPECT_EQ(tool->fields.at("mode").items.size(), 2u);
    EXPECT_EQ(scene.section("bench"), nullptr);
    // the document as read keeps it; the Model's physics document does not
    EXPECT_EQ(scene.document->fields.count("my_tool"), 1u);
    EXPECT_EQ(scene.model.document->fields.count("my_tool"), 0u);
    EXPECT_EQ(scene.model.body_count(), 1);
    EXPECT_EQ(scene.model.bodies[0].mass, 2.0);
    // a parameter study loads the physics again, with no application declared
    const mbd::Model heavier =
        mbd::with_scene_parameters(scene.model, {{"bodies.rod.mass", 3.0}}, mbd::test::shared_registry());
    EXPECT_EQ(heavier.bodies[0].mass, 3.0);
}

TEST(SceneSections, BenchAndStabilityReadTheirSectionsFromTheScene) {
    mbd::Registry& registry = mbd::test::shared_registry();
    const mbd::Scene bench = mbd::read_scene(mbd::test::scene_path("bench/gyroscope.yaml"), registry);
    ASSERT_NE(bench.section(mbd::kBenchSection), nullptr);
    const mbd::BenchSpec spec = mbd::load_bench_spec(bench);
    EXPECT_GT(spec.t_end, 0.0);
    EXPECT_EQ(spec.name, "gyroscope");
    EXPECT_THROW(mbd::read_expectation(bench), mbd::InputError);  // it declares no outcome
    const mbd::Scene extreme = mbd::read_scene(mbd::test::scene_path("extreme/bricard-dynamics.yaml"), registry);
    const mbd::Expectation e = mbd::read_expectation(extreme);
    EXPECT_TRUE(e.pass || !e.kinds.empty());
    EXPECT_THROW(mbd::load_bench_spec(extreme), mbd::InputError);
    // the Model-returning entry point still loads both (the sections this process declared)
    EXPECT_EQ(mbd::load_scene(mbd::test::scene_path("bench/gyroscope.yaml"), registry).name, "gyroscope");
    EXPECT_GT(mbd::load_scene(mbd::test::scene_path("extreme/bricard-dynamics.yaml"), registry).body_count(), 0);
}

TEST(SceneSections, EveryTestProgramDeclaresTheApplicationsSections) {
    // tests/support/application_sections.cpp declares them at start-up (an object library, so the
    // linker keeps it): without it the default of read_scene_text would refuse `bench:`
    std::vector<std::string> names;
    for (const mbd::SceneSection& s : mbd::declared_scene_sections()) names.push_back(s.key);
    EXPECT_NE(std::find(names.begin(), names.end(), mbd::kBenchSection), names.end());
    EXPECT_NE(std::find(names.begin(), names.end(), mbd::kExpectSection), names.end());
    const mbd::Scene scene = mbd::read_scene_text(kPendulum + "bench: {t_end: 1}\n", "scene.yaml",
                                                  mbd::test::shared_registry());
    EXPECT_NE(scene.section(mbd::kBenchSection), nullptr);
}

}  // namespace
