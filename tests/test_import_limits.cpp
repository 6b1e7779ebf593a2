// Issue 37, joint limits imported as joint stops (import/src/scene_builder.cpp, add_stop; docs/import.md,
// "Joint limits"): a block on a vertical prismatic joint falls freely (closed form s = -g t^2 / 2)
// until its lower limit, stops there (a plastic impact) and is held by the stop's linear spring
// of the file's stiffness: it then oscillates between the limit and twice the static deflection
// m g / k below it. URDF (Gazebo's stiffness 1e8 for a URDF limit) and SDF (<limit><stiffness>).
#include "support/mujoco_oracle.hpp"
#include "support/input_files.hpp"
#include "support/test_support.hpp"

#include <mbd/import/import.hpp>
#include <mbd/import/scene_writer.hpp>

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

namespace mbd::test {
namespace {

namespace fs = std::filesystem;

fs::path write_file(const std::string& name, const std::string& content) {
    return write_scratch_file("import_limits", name, content);
}

constexpr double kMass = 2.0, kLower = -0.2;

// The block's travel along the joint (from its start; its mass centre lies 0.1 m below the
// joint's origin, so the stop's travel is shifted by that on import) every `step` s over t_end.
std::vector<double> travel(const fs::path& model_file, double g, double t_end, double step) {
    const import::ImportedScene scene = import::import_model(model_file);
    EXPECT_EQ(scene.stops.size(), 1u);
    const Model model = load_scene_text(import::scene_yaml(scene), "limits.yaml", shared_registry());
    std::vector<double> s;
    for (const Eigen::VectorXd& q : mbd_run(model, t_end, step)) s.push_back(q[2] - (1.0 - 0.1));
    EXPECT_NEAR(-0.5 * g * 0.1 * 0.1, s[std::lround(0.1 / step)], 1e-10);  // free fall before the limit
    return s;
}

TEST(ImportLimits, UrdfPrismaticLimitStopsAFallingBlock) {
    const fs::path urdf = write_file("slider.urdf", R"(<?xml version="1.0"?>
<robot name="slider">
  <link name="base"/>
  <link name="block"><inertial><mass value="2"/><origin xyz="0 0 -0.1"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <joint name="rail" type="prismatic"><parent link="base"/><child link="block"/><origin xyz="0 0 1"/>
    <axis xyz="0 0 1"/><limit lower="-0.2" upper="0.5" effort="1" velocity="1"/></joint>
</robot>
)");
    const double g = 9.81, k = 1e8, deflection = kMass * g / k;
    const std::vector<double> s = travel(urdf, g, 0.5, 0.01);
    // hits at sqrt(2 * 0.2 / g) = 0.202 s; from 0.21 s on it stays within the spring's swing
    for (size_t i = 21; i < s.size(); ++i) {
        EXPECT_LE(s[i], kLower + 1e-9) << i;
        EXPECT_GE(s[i], kLower - 2 * deflection - 1e-9) << i;
    }
}

// MJCF: the same block on a slide with range="-0.2 0.5". MuJoCo's limit is soft (solref 0.02 s:
// the block would sink into it by about m g timeconst^2 / m = g (0.02 s)^2 ~ 4 mm at rest); mbd's
// stop is the stiff one of a URDF limit (1e8), so the block is held within 2 m g / k of it.
TEST(ImportLimits, MjcfSlideRangeStopsAFallingBlock) {
    const fs::path mjcf = write_file("slider.xml", R"(<mujoco model="slider">
  <option gravity="0 0 -9.81"/>
  <worldbody><body name="block" pos="0 0 1">
    <joint name="rail" type="slide" axis="0 0 1" limited="true" range="-0.2 0.5"/>
    <inertial pos="0 0 -0.1" mass="2" diaginertia="0.01 0.01 0.01"/></body></worldbody>
</mujoco>
)");
    const double g = 9.81, deflection = kMass * g / 1e8;
    const std::vector<double> s = travel(mjcf, g, 0.5, 0.01);
    for (size_t i = 21; i < s.size(); ++i) {
        EXPECT_LE(s[i], kLower + 1e-9) << i;
        EXPECT_GE(s[i], kLower - 2 * deflection - 1e-9) << i;
    }
}

TEST(ImportLimits, SdfLimitStiffnessHoldsTheBlock) {
    const fs::path sdf = write_file("slider.sdf", R"(<?xml version="1.0"?>
<sdf version="1.9"><model name="slider">
  <link name="block"><pose>0 0 1 0 0 0</pose>
    <inertial><mass>2</mass><pose>0 0 -0.1 0 0 0</pose>
      <inertia><ixx>0.01</ixx><iyy>0.01</iyy><izz>0.01</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia></inertial></link>
  <joint name="rail" type="prismatic"><parent>world</parent><child>block</child>
    <axis><xyz>0 0 1</xyz><limit><lower>-0.2</lower><upper>0.5</upper><stiffness>1e4</stiffness></limit></axis></joint>
</model></sdf>
)");
    const double g = 9.8, k = 1e4, deflection = kMass * g / k;  // 1.96 mm; period 2 pi sqrt(m / k) = 89 ms
    const std::vector<double> s = travel(sdf, g, 0.5, 0.001);
    double deepest = 0.0;
    for (size_t i = 210; i < s.size(); ++i) deepest = std::min(deepest, s[i] - kLower);
    std::printf("SDF limit: deepest %.6g m past the limit, 2 m g / k = %.6g m\n", -deepest, 2 * deflection);
    EXPECT_NEAR(-deepest, 2 * deflection, 0.02 * deflection);  // sampled every 1 ms of an 89 ms swing
}

// A range that the start lies outside is not a stop (it would throw the joint back at once with
// the stop's full stiffness) but listed; --position inside the range makes it a stop again.
TEST(ImportLimits, ARangeTheStartViolatesIsListedNotStopped) {
    const fs::path urdf = write_file("outside.urdf", R"(<?xml version="1.0"?>
<robot name="outside"><link name="base"/>
  <link name="block"><inertial><mass value="2"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <joint name="rail" type="prismatic"><parent link="base"/><child link="block"/><axis xyz="0 0 1"/>
    <limit lower="0.1" upper="0.5" effort="1" velocity="1"/></joint>
</robot>
)");
    const import::ImportedScene outside = import::import_model(urdf);
    EXPECT_TRUE(outside.stops.empty());
    EXPECT_NE(import::unmapped_summary(outside.unmapped).find("joint limits that the start violates (rail)"), std::string::npos)
        << import::unmapped_summary(outside.unmapped);
    import::ImportOptions options;
    options.joint_positions = {{"rail", 0.3}};
    const import::ImportedScene inside = import::import_model(urdf, options);
    ASSERT_EQ(inside.stops.size(), 1u);
    // the stop measures the travel from the joint's point on the base, where the block's mass
    // centre was at the reference: the block starts at 0.3 and the range stays 0.1..0.5
    EXPECT_NEAR(inside.stops[0].lower, 0.1, 1e-15);
    EXPECT_NEAR(inside.stops[0].upper, 0.5, 1e-15);
    EXPECT_NEAR(inside.bodies[0].position.z(), 0.3, 1e-15);
}

}  // namespace
}  // namespace mbd::test
