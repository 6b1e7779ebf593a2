// Messages about a plugin element's keys (core/src/scene/scene_loader.hpp, create_checked): a key
// the type describes (mbd/sdk/plugin_keys.hpp) is never called unknown, also when the plugin
// stops at another key before reading it (issue 42: kinetic_friction, radius, exponent and
// follower_point were); an unknown key lists the type's valid keys; a described key that the
// other keys make meaningless is named as such.
#include "support/test_support.hpp"

#include <gtest/gtest.h>

namespace mbd {
namespace {

const std::string planar_bodies =
    "dimension: planar\n"
    "bodies:\n"
    "  - {name: a, mass: 1, inertia: 0.1, position: [0, 0]}\n"
    "  - {name: b, mass: 1, inertia: 0.1, position: [1, 0]}\n";

const std::string spatial_bodies =
    "dimension: spatial\n"
    "bodies:\n"
    "  - {name: a, mass: 1, inertia: [0.1, 0.1, 0.1], position: [0, 0, 0]}\n"
    "  - {name: b, mass: 1, inertia: [0.1, 0.1, 0.1], position: [1, 0, 0]}\n";

// The message of the error loading `yaml` raises ("" when it loads).
std::string load_error(const std::string& yaml) {
    try {
        test::scene(yaml);
    } catch (const InputError& e) {
        return e.what();
    }
    return {};
}

struct Case {
    const char* what;
    std::string yaml;
    const char* expected;  // the real cause, which the message must name
    const char* key;       // the valid key that must not be called unknown
};

TEST(PluginKeyMessages, ValidKeysAreNeverCalledUnknown) {
    const std::vector<Case> cases = {
        {"coulomb_friction, static_friction negative", planar_bodies +
             "forces:\n  - {name: dry, type: coulomb_friction, bodies: [a, b], normal_force: 10,\n"
             "     static_friction: -0.1, kinetic_friction: 0.1}\n",
         "'static_friction' must not be negative", "kinetic_friction"},
        {"sphere_plane, static_friction negative", spatial_bodies +
             "forces:\n  - {name: floor, type: sphere_plane, bodies: [a, b], normal: [0, 0, 1], radius: 0.1,\n"
             "     stiffness: 1.0e5, static_friction: -0.3, kinetic_friction: 0.2}\n",
         "'static_friction' must not be negative", "kinetic_friction"},
        {"rotational_friction without its load", planar_bodies +
             "forces:\n  - {name: pin, type: rotational_friction, bodies: [a, b], radius: 0.02,\n"
             "     static_friction: 0.3, kinetic_friction: 0.2}\n",
         "missing key 'normal_force'", "radius"},
        {"circle_line, stiffness negative", planar_bodies +
             "forces:\n  - {name: floor, type: circle_line, bodies: [a, b], normal: [0, 1], radius: 0.1,\n"
             "     stiffness: -5, exponent: 1.5}\n",
         "'stiffness' must be positive", "exponent"},
        {"joint_stop, restitution above 1", planar_bodies +
             "joints:\n  - {name: pin, type: revolute, bodies: [a, b], point: [0.5, 0]}\n"
             "forces:\n  - {name: stop, type: joint_stop, bodies: [a, b], point: [0.5, 0], upper: 0.3,\n"
             "     restitution: 2, law: hunt_crossley, stiffness: 100, exponent: 1.5}\n",
         "'restitution' must lie in [0, 1]", "exponent"},
        {"cam, a misspelt follower", planar_bodies +
             "joints:\n  - {name: contact, type: cam, bodies: [a, b], point: [0, 0],\n"
             "     profile: {type: eccentric, radius: 0.1, eccentricity: 0.02}, follower: rollr,\n"
             "     radius: 0.03, follower_point: [0, 0]}\n",
         "unknown follower 'rollr'", "follower_point"},
        {"cam, a misspelt follower (the roller radius)", planar_bodies +
             "joints:\n  - {name: contact, type: cam, bodies: [a, b], point: [0, 0],\n"
             "     profile: {type: eccentric, radius: 0.1, eccentricity: 0.02}, follower: rollr,\n"
             "     radius: 0.03, follower_point: [0, 0]}\n",
         "unknown follower 'rollr'", "radius"}};
    for (const Case& c : cases) {
        const std::string message = load_error(c.yaml);
        EXPECT_NE(message.find(c.expected), std::string::npos) << c.what << ": " << message;
        EXPECT_EQ(message.find("unknown key '" + std::string(c.key) + "'"), std::string::npos) << c.what << ": " << message;
        EXPECT_EQ(message.find("unknown key"), std::string::npos) << c.what << ": " << message;
    }
}

// A misspelt key is still found when the plugin fails for want of the right one, and the
// message lists the type's keys.
TEST(PluginKeyMessages, AMisspeltKeyIsNamedWithTheValidKeys) {
    const std::string message = load_error(
        planar_bodies + "forces:\n  - {name: spring, type: spring_damper, bodies: [a, b], stifness: 100}\n");
    EXPECT_NE(message.find("unknown key 'stifness' at line 6: did you mean 'stiffness'?"), std::string::npos) << message;
    EXPECT_NE(message.find("'damping', 'rest_length', 'force'"), std::string::npos) << message;
    EXPECT_NE(message.find("mbd plugins --keys spring_damper"), std::string::npos) << message;
}

// An unknown key on an element that loads otherwise: refused, listing every valid key.
TEST(PluginKeyMessages, AnUnknownKeyListsTheValidKeys) {
    const std::string message = load_error(planar_bodies +
                                           "joints:\n  - {name: nut, type: revolute, bodies: [a, b], colour: red}\n");
    EXPECT_NE(message.find("test.yaml:6: unknown key 'colour' in joint 'nut'"), std::string::npos) << message;
    EXPECT_NE(message.find("the keys of a joint of type 'revolute' are 'axis', 'bodies', 'limits', 'name', 'point', "
                           "'type'"),
              std::string::npos)
        << message;
}

// A described key that the other keys leave without effect is named as such, not as unknown.
TEST(PluginKeyMessages, AValidKeyWithoutEffectIsNamedAsSuch) {
    const std::string message = load_error(
        planar_bodies +
        "joints:\n  - {name: contact, type: cam, bodies: [a, b], point: [0, 0],\n"
        "     profile: {type: eccentric, radius: 0.1, eccentricity: 0.02}, follower: knife_edge,\n"
        "     radius: 0.03, follower_point: [0, 0.2]}\n");
    EXPECT_NE(message.find("key 'radius' is a key of the joint type 'cam' but it has no effect with the other keys "
                           "given here (radius: the roller radius (m), > 0; roller followers only)"),
              std::string::npos)
        << message;
    EXPECT_EQ(message.find("unknown key"), std::string::npos) << message;
}

}  // namespace
}  // namespace mbd
