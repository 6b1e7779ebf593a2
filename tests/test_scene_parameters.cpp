// Scene keys addressed by a path (core scene_parameters.hpp), the mechanism behind studies:
// a Model changed through its document must equal the Model of the scene file edited by hand,
// down to the last bit of a simulation, and a path that does not resolve is refused naming
// the segment and the nearest names.
#include <mbd/scene_parameters.hpp>
#include <mbd/simulation.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include "support/test_support.hpp"

namespace {

#define EXPECT_CONTAINS(text, part) \
    EXPECT_NE(std::string(text).find(part), std::string::npos) << "'" << (text) << "' lacks '" << (part) << "'"

using mbd::test::shared_registry;

std::string replace(std::string text, const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << "test bug: '" << from << "' not in the scene";
    if (at != std::string::npos) text.replace(at, from.size(), to);
    return text;
}

mbd::State final_state(const mbd::Model& model) {
    mbd::SimulationSettings settings;
    settings.integrator = "rk4";
    settings.integration.step = 1e-3;
    settings.t_end = 0.2;
    settings.progress = false;
    settings.messages = mbd::MessageLog::silent();
    return mbd::simulate(model, shared_registry(), settings).final_state;
}

std::string parameter_error(const mbd::Model& model, const std::string& path, double value) {
    try {
        mbd::with_scene_parameters(model, {{path, value}}, shared_registry());
    } catch (const mbd::InputError& e) {
        return e.what();
    }
    ADD_FAILURE() << "expected an InputError for " << path;
    return {};
}

const std::string kSliderCrank = "dynamics/slider-crank.yaml";

TEST(SceneParameters, ReadsTheValuesWrittenInTheScene) {
    const mbd::Model model = mbd::test::load(kSliderCrank);
    EXPECT_EQ(mbd::scene_parameter(*model.document, "bodies.crank.mass"), 0.5);
    EXPECT_EQ(mbd::scene_parameter(*model.document, "bodies[1].mass"), 1.0);
    EXPECT_EQ(mbd::scene_parameter(*model.document, "bodies.2.inertia"), 0.0005);
    EXPECT_EQ(mbd::scene_parameter(*model.document, "joints.guide.point[0]"), 0.5155870949147037);
    EXPECT_EQ(mbd::scene_parameter(*model.document, "forces.spring.points[0][0]"), 0.8);
    EXPECT_EQ(mbd::scene_parameter(*model.document, "gravity[1]"), -9.81);
}

// Each change gives the same trajectory, bit for bit, as the scene text edited by hand.
TEST(SceneParameters, AChangedModelEqualsTheEditedSceneBitForBit) {
    const mbd::Model model = mbd::test::load(kSliderCrank);
    const std::string text = mbd::test::read_text(mbd::test::scene_path(kSliderCrank));
    struct Case {
        std::string path;
        double value;
        std::string from, to;
    };
    const Case cases[] = {
        {"bodies.crank.mass", 2.0, "mass: 0.5", "mass: 2.0"},
        {"forces.spring.stiffness", 1e4, "stiffness: 100", "stiffness: 10000"},
        {"bodies.crank.angular_velocity", 3.5, "angular_velocity: 10.0", "angular_velocity: 3.5"},
        {"forces.spring.points[0][0]", 0.9, "[[0.8, 0.0]", "[[0.9, 0.0]"},
        {"gravity[1]", -1.62, "gravity: [0, -9.81]", "gravity: [0, -1.62]"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.path);
        const mbd::Model changed = mbd::with_scene_parameters(model, {{c.path, c.value}}, shared_registry());
        const mbd::Model edited = mbd::test::scene(replace(text, c.from, c.to), "edited.yaml");
        EXPECT_EQ(mbd::scene_parameter(*changed.document, c.path), c.value);
        const mbd::State a = final_state(changed), b = final_state(edited);
        EXPECT_EQ(a.q, b.q);
        EXPECT_EQ(a.v, b.v);
        EXPECT_NE(a.q, final_state(model).q) << "the change must matter";
    }
    EXPECT_EQ(model.bodies[0].mass, 0.5) << "the original Model is not changed";
}

// A key the scene leaves out: created where the map that holds it exists; an absent vector
// starts as zeros of the scene's dimension.
TEST(SceneParameters, AnAbsentKeyIsCreated) {
    const mbd::Model model = mbd::test::load(kSliderCrank);
    const mbd::Model changed =
        mbd::with_scene_parameters(model, {{"bodies.rod.velocity[1]", 0.25}, {"bodies.slider.angular_velocity", 1.5}},
                                   shared_registry());
    EXPECT_EQ(changed.bodies[1].velocity, mbd::Vec3(0.0, 0.25, 0.0));
    EXPECT_EQ(changed.bodies[2].angular_velocity.z(), 1.5);
    EXPECT_EQ(mbd::scene_parameter(*changed.document, "bodies.rod.velocity[0]"), 0.0);
}

TEST(SceneParameters, APathThatDoesNotResolveNamesTheSegmentAndNearMatches) {
    const mbd::Model model = mbd::test::load(kSliderCrank);
    std::string e = parameter_error(model, "bodies.crnak.mass", 1.0);
    EXPECT_CONTAINS(e, "parameter 'bodies.crnak.mass'");
    EXPECT_CONTAINS(e, "no element named 'crnak' in 'bodies'");
    EXPECT_CONTAINS(e, "did you mean 'crank'?");
    e = parameter_error(model, "bodeis.crank.mass", 1.0);
    EXPECT_CONTAINS(e, "no key 'bodeis' at the top of the scene; did you mean 'bodies'?");
    e = parameter_error(model, "joints.O.point[2]", 1.0);
    EXPECT_CONTAINS(e, "'joints.O.point' has 2 items, no [2]");
    e = parameter_error(model, "joints.O.point", 1.0);
    EXPECT_CONTAINS(e, "is a list; address one number in it with [i]");
    e = parameter_error(model, "bodies.crank.mass", std::numeric_limits<double>::quiet_NaN());
    EXPECT_CONTAINS(e, "must be a finite number");
    e = parameter_error(model, "bodies..mass", 1.0);
    EXPECT_CONTAINS(e, "an empty key");
    e = parameter_error(model, "bodies.crank.mass[x]", 1.0);
    EXPECT_CONTAINS(e, "is not an index");
    // a misspelt key in an element is created and refused by the scene loader, with the change named
    e = parameter_error(model, "bodies.crank.mas", 1.0);
    EXPECT_CONTAINS(e, "unknown key 'mas'");
    EXPECT_CONTAINS(e, "did you mean 'mass'?");
    EXPECT_CONTAINS(e, "(with bodies.crank.mas = 1)");
    // a value the scene refuses: the loader's message and the change that caused it
    e = parameter_error(model, "bodies.crank.mass", -1.0);
    EXPECT_CONTAINS(e, "slider-crank.yaml:");
    EXPECT_CONTAINS(e, "(with bodies.crank.mass = -1)");
}

// A refused path is a ParameterError that names it (Python's SceneError.key).
TEST(SceneParameters, ARefusedPathIsAParameterErrorNamingIt) {
    const mbd::Model model = mbd::test::load(kSliderCrank);
    try {
        mbd::with_scene_parameters(model, {{"bodies.crnak.mass", 1.0}}, shared_registry());
        FAIL() << "expected a ParameterError";
    } catch (const mbd::ParameterError& e) {
        EXPECT_EQ(e.path(), "bodies.crnak.mass");
    }
}

// The key at a file:line of scenes/dynamics/slider-crank.yaml, read back from the document
// that load_scene keeps and from read_scene_document: each resolves to the node at that line.
TEST(SceneParameters, TheKeyAtALineIsThePathOfItsNode) {
    const mbd::Model model = mbd::test::load(kSliderCrank);
    const std::string file = mbd::test::scene_path(kSliderCrank).string();
    const mbd::Param read = mbd::read_scene_document(file);
    for (const mbd::Param* document : {model.document.get(), &read}) {
        EXPECT_EQ(mbd::scene_key_at(*document, file, 15), "gravity");
        EXPECT_EQ(mbd::scene_key_at(*document, file, 17), "bodies.crank");  // "- name: crank": the element
        EXPECT_EQ(mbd::scene_key_at(*document, file, 18), "bodies.crank.mass");
        EXPECT_EQ(mbd::scene_key_at(*document, file, 30), "bodies.slider.inertia");
        EXPECT_EQ(mbd::scene_key_at(*document, file, 37), "joints.guide");  // a one-line element
        EXPECT_EQ(mbd::scene_key_at(*document, file, 43), "forces.spring.stiffness");
        EXPECT_EQ(mbd::scene_key_at(*document, file, 12), "");  // a comment
        EXPECT_EQ(mbd::scene_key_at(*document, "other.yaml", 18), "");
    }
    // every key found is a path that resolves to a number written at that line
    EXPECT_EQ(mbd::scene_parameter(read, mbd::scene_key_at(read, file, 43)), 100.0);
    EXPECT_EQ(mbd::scene_parameter(read, mbd::scene_key_at(read, file, 30)), 0.0005);
    // an element without a name (a scene the loader refuses, with the key named) by its position
    const std::filesystem::path unnamed = mbd::test::scratch("key-at") / "u.yaml";
    std::ofstream(unnamed) << "dimension: planar\nbodies:\n  - mass: 1\n    inertia: 2\n";
    const mbd::Param document = mbd::read_scene_document(unnamed);
    EXPECT_EQ(mbd::scene_key_at(document, unnamed.string(), 3), "bodies.0");
    EXPECT_EQ(mbd::scene_key_at(document, unnamed.string(), 4), "bodies.0.inertia");
    EXPECT_EQ(mbd::scene_parameter(document, "bodies.0.inertia"), 2.0);
}

}  // namespace
