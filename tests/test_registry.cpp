// The plugin registry: discovery without loading, loading only what a scene
// uses, and clear refusals (unknown type, wrong ABI).
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>

namespace mbd {
namespace {

std::vector<std::string> file_names(const std::vector<std::string>& paths) {
    std::vector<std::string> names;
    for (const auto& p : paths) names.push_back(std::filesystem::path(p).filename().string());
    return names;
}

TEST(Registry, FindsEveryStandardTypeWithoutLoadingAnything) {
    Registry registry({test::build_plugin_dir()});
    for (const char* type : {"revolute", "prismatic", "fixed", "gear_pair", "rack_pinion", "cylindrical", "spherical",
                             "universal", "planar", "screw"})
        EXPECT_TRUE(registry.has("joint", type)) << type;
    for (const char* type :
         {"gravity", "spring_damper", "rotational_spring_damper", "bushing", "point_force", "point_torque"})
        EXPECT_TRUE(registry.has("force", type)) << type;
    EXPECT_TRUE(registry.loaded_libraries().empty());
    for (const PluginType& t : registry.types()) {
        EXPECT_EQ(t.abi, MBD_ABI_VERSION);
        EXPECT_EQ(t.version, MBD_TEST_VERSION) << t.library;  // read from the file, not loaded
        // one shared library per joint type and per force type
        if (t.kind == "joint" || t.kind == "force")
            EXPECT_EQ(t.library.filename().string(), "libmbd_" + t.kind + "_" + t.type + ".so");
    }
}

TEST(Registry, SceneWithRevoluteJointsAndGravityOpensExactlyThoseTwoLibraries) {
    Registry registry({test::build_plugin_dir()});
    const std::string scene = R"(
name: double pendulum
dimension: planar
gravity: [0, -9.81]
bodies:
  - {name: upper, mass: 1, inertia: 0.1, position: [0.5, 0], angle: 0}
  - {name: lower, mass: 1, inertia: 0.1, position: [1.5, 0], angle: 0}
joints:
  - {name: shoulder, type: revolute, bodies: [ground, upper], point: [0, 0]}
  - {name: elbow, type: revolute, bodies: [upper, lower], point: [1, 0]}
)";
    Model model = load_scene_text(scene, "double-pendulum.yaml", registry);
    EXPECT_EQ(model.joints.size(), 2u);
    auto opened = file_names(registry.loaded_libraries());
    std::sort(opened.begin(), opened.end());
    EXPECT_EQ(opened, (std::vector<std::string>{"libmbd_force_gravity.so", "libmbd_joint_revolute.so"}));
}

TEST(Registry, UnknownTypeListsTheKnownOnes) {
    Registry registry({test::build_plugin_dir()});
    JointSpec spec;
    spec.name = "hinge";
    spec.type = "revolut";
    try {
        registry.create_joint(spec, "scene.yaml:12");
        FAIL() << "expected an error";
    } catch (const PluginError& e) {  // an InputError (bad input) of its own class, for Python's mbd.PluginError
        const std::string what = e.what();
        EXPECT_NE(what.find("scene.yaml:12"), std::string::npos) << what;
        EXPECT_NE(what.find("unknown joint type 'revolut'"), std::string::npos) << what;
        EXPECT_NE(what.find("revolute"), std::string::npos) << what;
        EXPECT_NE(what.find("spherical"), std::string::npos) << what;
    }
    EXPECT_TRUE(registry.loaded_libraries().empty());
}

TEST(Registry, PluginOfAnotherAbiIsListedAndRefusedWithoutLoading) {
    Registry registry({test::build_plugin_dir(), std::filesystem::path(MBD_TEST_PLUGIN_DIR)});
    bool listed = false;
    for (const PluginType& t : registry.types())
        if (t.type == "old_joint") {
            listed = true;
            EXPECT_EQ(t.abi, 999);
        }
    EXPECT_TRUE(listed);
    EXPECT_FALSE(registry.has("joint", "old_joint"));
    ASSERT_FALSE(registry.problems().empty());
    EXPECT_NE(registry.problems().front().find("ABI 999"), std::string::npos);

    JointSpec spec;
    spec.name = "legacy";
    spec.type = "old_joint";
    try {
        registry.create_joint(spec, "scene.yaml:3");
        FAIL() << "expected an ABI error";
    } catch (const PluginError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("ABI 999"), std::string::npos) << what;
        EXPECT_NE(what.find("rebuild"), std::string::npos) << what;
    }
    EXPECT_TRUE(registry.loaded_libraries().empty());
}

TEST(Registry, PluginPathEnvironmentVariableAddsFolders) {
    ::setenv("MBD_PLUGIN_PATH", MBD_TEST_PLUGIN_DIR, 1);
    const auto path = Registry::default_search_path();
    ::unsetenv("MBD_PLUGIN_PATH");
    ASSERT_GE(path.size(), 2u);
    EXPECT_EQ(path.back(), std::filesystem::path(MBD_TEST_PLUGIN_DIR));
    // the first folder is the plugin folder beside libmbd_core in this build tree
    EXPECT_EQ(std::filesystem::weakly_canonical(path.front()), std::filesystem::weakly_canonical(test::build_plugin_dir()));
}

}  // namespace
}  // namespace mbd
