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

// The problem the registry reports for a library that names `what`, or "" when none does.
std::string problem_naming(const Registry& registry, const std::string& what) {
    for (const std::string& p : registry.problems())
        if (p.find(what) != std::string::npos) return p;
    return "";
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
    EXPECT_TRUE(registry.has("formulation", "augmented"));
    EXPECT_TRUE(registry.has("statics", "ipopt"));
    for (const PluginType& t : registry.types()) {
        // element plugins carry the SDK's ABI, the formulation kit's plugins the kit's
        const bool kit = t.kind == "formulation" || t.kind == "statics" || t.kind == "inverse";
        EXPECT_EQ(t.abi, kit ? MBD_KIT_ABI_VERSION : MBD_ABI_VERSION) << t.kind << " " << t.type;
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
    EXPECT_NE(problem_naming(registry, "joint type 'old_joint' was built for plugin ABI 999, this mbd uses ABI " +
                                           std::to_string(MBD_ABI_VERSION) + "; rebuild it against this SDK"),
              "");

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

TEST(Registry, FormulationOfAnotherKitAbiIsListedAndRefusedWithAClearMessage) {
    // tests/plugins/wrong_kit_abi.cpp: kit ABI 999, and the SDK's ABI where the kit's belongs
    Registry registry({test::build_plugin_dir(), std::filesystem::path(MBD_TEST_PLUGIN_DIR)});
    int listed = 0;
    for (const PluginType& t : registry.types())
        if (t.type == "old_formulation" || t.type == "sdk_abi_formulation") {
            ++listed;
            EXPECT_EQ(t.abi, t.type == "old_formulation" ? 999 : MBD_ABI_VERSION);
        }
    EXPECT_EQ(listed, 2);
    EXPECT_FALSE(registry.has("formulation", "old_formulation"));
    EXPECT_FALSE(registry.has("formulation", "sdk_abi_formulation"));
    const std::vector<std::string> usable = registry.type_names("formulation");
    EXPECT_EQ(std::count(usable.begin(), usable.end(), "sdk_abi_formulation"), 0);
    EXPECT_EQ(std::count(usable.begin(), usable.end(), "augmented"), 1);
    const std::string host = std::to_string(MBD_KIT_ABI_VERSION);
    EXPECT_NE(problem_naming(registry, "formulation type 'old_formulation' was built for formulation kit ABI 999, "
                                       "this mbd uses kit ABI " + host + "; rebuild it against this formulation kit"),
              "");
    EXPECT_NE(problem_naming(registry, "formulation type 'sdk_abi_formulation' was built for formulation kit ABI " +
                                           std::to_string(MBD_ABI_VERSION) + ", this mbd uses kit ABI " + host),
              "");

    for (const char* type : {"old_formulation", "sdk_abi_formulation"}) {
        FormulationSpec spec;
        spec.name = type;
        spec.type = type;
        try {
            registry.create_formulation(spec, "scene.yaml:7");
            FAIL() << "expected a kit ABI error for " << type;
        } catch (const PluginError& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find("scene.yaml:7"), std::string::npos) << what;
            EXPECT_NE(what.find("libmbd_formulation_wrong_kit_abi.so, built for formulation kit ABI "),
                      std::string::npos) << what;
            EXPECT_NE(what.find("but this mbd uses kit ABI " + host + "; rebuild the plugin against this formulation kit"),
                      std::string::npos) << what;
        }
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
