// Errors that name their real cause (issue 42, item 6): a mesh path that is a folder, a scene
// too large without any alias, an unterminated quote in the YAML, a driver whose time function
// overflows. Each of these was reported as something else (not found, aliases, a bad body name,
// the joint).
#include <mbd/scene.hpp>
#include <mbd/simulation.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "support/test_support.hpp"

namespace {

namespace fs = std::filesystem;
using mbd::test::write_text;

#define EXPECT_CONTAINS(text, part) \
    EXPECT_NE(std::string(text).find(part), std::string::npos) << "'" << (text) << "' lacks '" << (part) << "'"

// The message of the InputError loading the scene file throws, or "loaded".
std::string file_error(const fs::path& file) {
    try {
        mbd::load_scene(file, mbd::test::shared_registry());
    } catch (const mbd::InputError& e) {
        return e.what();
    }
    return "loaded";
}

std::string text_error(const std::string& yaml) {
    try {
        mbd::test::scene(yaml);
    } catch (const mbd::InputError& e) {
        return e.what();
    }
    return "loaded";
}

const std::string kBob = "dimension: planar\nbodies:\n  - name: bob\n    mass: 1\n    inertia: 0.01\n"
                         "    visual: {shape: mesh, file: meshes}\n";

TEST(NamedCauses, AMeshPathThatIsAFolderIsCalledAFolder) {
    const fs::path dir = mbd::test::scratch("mesh-folder");
    const fs::path scene = write_text(dir / "scene.yaml", kBob);
    // no such path: not found
    EXPECT_CONTAINS(file_error(scene), "scene.yaml:6: body 'bob': key 'file': mesh file '" + (dir / "meshes").string() +
                                           "' not found");
    // a folder of that name: a folder, not "not found"
    fs::create_directory(dir / "meshes");
    const std::string message = file_error(scene);
    EXPECT_CONTAINS(message, "scene.yaml:6: body 'bob': key 'file': '" + (dir / "meshes").string() + "' is a folder");
    EXPECT_EQ(message.find("not found"), std::string::npos) << message;
}

TEST(NamedCauses, AScenePastTheValueLimitWithoutAliasesIsToldTheLimitNotAboutAliases) {
    // 100,000 bodies written out (7 values each) were refused with a message about aliases;
    // the values are counted before any key is read, so a list of 250,001 numbers (no alias)
    // reaches the limit the same way and parses in a fifth of the time
    std::string text = "dimension: planar\nbodies: [0";
    for (size_t k = 1; k <= mbd::SceneLimits::max_values; ++k) text += ", 0";
    const std::string message = text_error(text + "]\n");
    EXPECT_CONTAINS(message, "test.yaml:2: the scene has more than " + std::to_string(mbd::SceneLimits::max_values) +
                                 " values (each number, name, list and map counts one");
    EXPECT_CONTAINS(message, "a scene may have at most " + std::to_string(mbd::SceneLimits::max_values) + " values");
    EXPECT_EQ(message.find("alias"), std::string::npos) << message;
}

TEST(NamedCauses, AnUnterminatedQuoteIsAYamlErrorWhereItOpens) {
    // yaml-cpp reads an unclosed quote on to the end of the file, so the body's name swallowed
    // the rest of the scene and the message was about the characters of that name
    const std::string scene = "dimension: planar\nbodies:\n  - name: ok\n    mass: 1\n    inertia: 0.01\n"
                              "  - name: QbobQ\n    mass: 1\n    inertia: 0.01\n";
    for (const char* quote : {"\"", "'"}) {
        std::string unclosed = scene;
        unclosed.replace(unclosed.find("QbobQ"), 5, std::string(quote) + "bob");
        const std::string message = text_error(unclosed);
        EXPECT_CONTAINS(message, std::string("test.yaml:6: YAML syntax error at test.yaml:6:11: the quoted value opened "
                                             "there (") + quote + ") is never closed");
        EXPECT_EQ(message.find("may only contain"), std::string::npos) << message;
        // closed, the same quote is a name like any other
        std::string closed = scene;
        closed.replace(closed.find("QbobQ"), 5, std::string(quote) + "bob" + quote);
        EXPECT_EQ(text_error(closed), "loaded") << quote;
    }
    // quotes inside a closed value are not openings: an escaped one, and '' in single quotes
    EXPECT_EQ(text_error("dimension: planar\nname: \"a \\\" b\"\nbodies:\n  - {name: x, mass: 1, inertia: 0.01}\n"),
              "loaded");
    EXPECT_EQ(text_error("dimension: planar\nname: 'it''s'\nbodies:\n  - {name: x, mass: 1, inertia: 0.01}\n"),
              "loaded");
}

TEST(NamedCauses, ADriverWhoseMotionOverflowsIsBlamedNotItsJoint) {
    // f = t + 1e307 t^2: finite, but its rates square to infinity in the pin's gamma; the
    // recursive path (embedding) blamed the pin, augmented reported a step size collapse
    const mbd::Model model = mbd::test::scene(
        "dimension: planar\ngravity: [0, -9.81]\nbodies:\n  - {name: arm, mass: 1, inertia: 0.01, position: [0.5, 0]}\n"
        "joints:\n  - {name: pin, type: revolute, bodies: [ground, arm], point: [0, 0]}\n"
        "drivers:\n  - {name: spin, joint: pin, motion: {type: polynomial, coefficients: [0, 1, 1e307]}}\n");
    for (const char* formulation : {"embedding", "augmented"}) {
        try {
            mbd::simulate(model, mbd::test::shared_registry(), mbd::test::adaptive_run(formulation, "dop853", 1e-8, 1.0, 0.1),
                          [](const mbd::SimulationSample&) { return true; });
            ADD_FAILURE() << formulation << ": the run went on";
        } catch (const mbd::DynamicsError& e) {
            EXPECT_CONTAINS(e.what(), "driver 'spin' (test.yaml:8): its motion is too large for the equations at t = ")
                << formulation;
            EXPECT_CONTAINS(e.what(), "d2f/dt2 = 2e+307") << formulation;
            EXPECT_EQ(std::string(e.what()).find("joint 'pin'"), std::string::npos) << e.what();
        }
    }
}

}  // namespace
