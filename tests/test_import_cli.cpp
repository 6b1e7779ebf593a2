// Issue 37: `mbd import` and model files wherever a scene is accepted (check, simulate), and bad
// model files: each a clear error naming the element (and the parser's line), exit 2, nothing
// written. The bad files are written into a scratch folder here.
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <regex>

namespace mbd::test {
namespace {

namespace fs = std::filesystem;

const std::string kHumanoid = "/usr/share/mujoco/model/humanoid/humanoid.xml";  // Debian libmujoco-samples

fs::path write_file(const std::string& name, const std::string& text) {
    static const fs::path dir = scratch("import_cli");
    std::ofstream(dir / name) << text;
    return dir / name;
}

// A two-link URDF arm; `arm_inertial` and `joint` replace its arm link's inertial and its joint.
std::string urdf(const std::string& arm_inertial, const std::string& joint) {
    return "<?xml version=\"1.0\"?>\n"
           "<robot name=\"arm\">\n"
           "  <link name=\"base\"/>\n"
           "  <link name=\"arm\">\n"
           "    <inertial>" + arm_inertial + "</inertial>\n"
           "  </link>\n" + joint + "\n</robot>\n";
}
const std::string kInertial =
    "<mass value=\"2\"/><origin xyz=\"0 0 -0.5\"/><inertia ixx=\"0.2\" ixy=\"0\" ixz=\"0\" iyy=\"0.2\" iyz=\"0\" izz=\"0.01\"/>";
const std::string kJoint =
    "  <joint name=\"shoulder\" type=\"revolute\">\n    <parent link=\"base\"/><child link=\"arm\"/>\n"
    "    <axis xyz=\"0 1 0\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/>\n  </joint>";

// `mbd import FILE -o OUT` fails with exit 2, names `expected` (each) on stderr and writes nothing.
void expect_refused(const fs::path& file, const std::vector<std::string>& expected) {
    const fs::path out = file.parent_path() / (file.stem().string() + "-scene.yaml");
    const CommandResult r = run_mbd("import " + file.string() + " -o " + out.string());
    EXPECT_EQ(r.exit_code, 2) << r.err;
    for (const std::string& e : expected) EXPECT_NE(r.err.find(e), std::string::npos) << "'" << e << "' not in: " << r.err;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_FALSE(fs::exists(out.string() + ".partial"));
}

TEST(ImportCli, HumanoidImportsWithOneWarningAndLoads) {
    const fs::path out = scratch("import_humanoid") / "humanoid.yaml";
    const CommandResult r = run_mbd("import " + kHumanoid + " -o " + out.string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    // one warning, naming what is left out: actuators, geoms (the armatures are rotors, the limits stops)
    EXPECT_EQ(r.err.find("mbd: warning:"), r.err.rfind("mbd: warning:")) << r.err;
    EXPECT_EQ(r.err.find("armature"), std::string::npos) << r.err;
    for (const char* left_out : {"21 actuators", "right_hip_x", "geoms"})
        EXPECT_NE(r.err.find(left_out), std::string::npos) << left_out << " in " << r.err;
    const std::string yaml = read_text(out);
    EXPECT_NE(yaml.find("# " + kHumanoid + ": MJCF body 'torso'"), std::string::npos);
    EXPECT_NE(yaml.find("name: right_knee, type: revolute"), std::string::npos);
    EXPECT_NE(yaml.find("name: right_knee_armature, type: coordinate_coupling"), std::string::npos);
    EXPECT_NE(yaml.find("name: right_knee_limits, type: joint_stop"), std::string::npos);
    // the written scene and the model file itself are accepted as scenes
    for (const std::string& scene : {out.string(), kHumanoid}) {
        const CommandResult check = run_mbd("check " + scene);
        EXPECT_EQ(check.exit_code, 0) << check.err;
        EXPECT_NE(check.out.find("degrees of freedom (rank of C_q): 27"), std::string::npos) << check.out;
    }
    const fs::path csv = out.parent_path() / "humanoid.csv";
    const CommandResult run = run_mbd("simulate " + kHumanoid + " --t-end 0.05 -q -o " + csv.string());
    EXPECT_EQ(run.exit_code, 0) << run.err;
    EXPECT_EQ(read_csv(csv).rows.size(), 1001u);
}

TEST(ImportCli, StrictRefusesWhatIsLeftOut) {
    const fs::path out = scratch("import_strict") / "humanoid.yaml";
    const CommandResult r = run_mbd("import " + kHumanoid + " --strict -o " + out.string());
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("--strict"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("21 actuators"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out));
}

TEST(ImportCli, MalformedXmlNamesTheParsersLine) {
    expect_refused(write_file("broken.xml", "<mujoco>\n  <worldbody>\n    <body name=\"a\">\n  </worldbody>\n</mujoco>\n"),
                   {"broken.xml", "Line number=3"});
    expect_refused(write_file("broken.urdf", "<robot name=\"r\">\n  <link name=\"a\">\n</robot>\n"),
                   {"broken.urdf:", "malformed XML"});
}

TEST(ImportCli, UrdfCycleIsRefusedByName) {
    const std::string joints =
        "  <joint name=\"j1\" type=\"revolute\"><parent link=\"base\"/><child link=\"arm\"/><axis xyz=\"0 1 0\"/></joint>\n"
        "  <joint name=\"j2\" type=\"revolute\"><parent link=\"arm\"/><child link=\"base\"/><axis xyz=\"0 1 0\"/></joint>";
    expect_refused(write_file("cycle.urdf", urdf(kInertial, joints)), {"cycle.urdf:", "cycle", "'j1'", "'j2'"});
}

TEST(ImportCli, NegativeMassIsRefusedByName) {
    expect_refused(write_file("negative.urdf", urdf(replaced(kInertial, "value=\"2\"", "value=\"-2\""), kJoint)),
                   {"negative.urdf", "link 'arm'", "mass -2"});
}

TEST(ImportCli, InertiaOutsideTheTriangleInequalityIsRefusedByName) {
    // principal moments 0.2, 0.2, 0.5: 0.5 exceeds 0.2 + 0.2
    expect_refused(write_file("plate.urdf", urdf(replaced(kInertial, "izz=\"0.01\"", "izz=\"0.5\""), kJoint)),
                   {"plate.urdf", "link 'arm'", "exceeds the sum of the other two"});
}

TEST(ImportCli, UnknownJointTypeIsRefusedByName) {
    expect_refused(write_file("hinge.urdf", urdf(kInertial, replaced(kJoint, "revolute", "hinge"))),
                   {"hinge.urdf:7:", "shoulder", "hinge"});
    expect_refused(write_file("screw.xml", "<mujoco>\n  <worldbody>\n    <body>\n      <joint name=\"s\" type=\"screw\"/>\n"
                                      "      <geom size=\"0.1\"/>\n    </body>\n  </worldbody>\n</mujoco>\n"),
                   {"screw.xml", "screw", "line 4"});
}

TEST(ImportCli, GoodUrdfImportsAndSimulates) {
    const fs::path file = write_file("good.urdf", urdf(kInertial, kJoint));
    const fs::path out = file.parent_path() / "good.yaml";
    const CommandResult r = run_mbd("import " + file.string() + " --velocity shoulder=2 -o " + out.string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string yaml = read_text(out);
    EXPECT_NE(yaml.find("name: shoulder_limits, type: joint_stop"), std::string::npos) << yaml;  // <limit> -1..1
    EXPECT_NE(yaml.find("coordinate: angle, lower: -1, upper: 1, restitution: 0"), std::string::npos) << yaml;
    EXPECT_NE(yaml.find("# " + file.string() + ":4: URDF link 'arm'"), std::string::npos) << yaml;
    // the arm's mass centre, 0.5 m below the shoulder turning at 2 rad/s about y: w x r = (-1, 0, 0) m/s
    EXPECT_NE(yaml.find("velocity: [-1, 0, 0]"), std::string::npos) << yaml;
    const CommandResult run = run_mbd("simulate " + out.string() + " --t-end 0.1 -q -o " + (file.parent_path() / "good.csv").string());
    EXPECT_EQ(run.exit_code, 0) << run.err;
}

// Every URDF joint type: continuous and revolute (1 DOF), prismatic (1), planar (3), floating (a
// free body, 6), fixed (the link merged into its parent: one body fewer).
TEST(ImportCli, UrdfJointTypesMap) {
    std::string links, joints;
    const std::vector<std::pair<std::string, std::string>> types{
        {"a", "continuous"}, {"b", "prismatic"}, {"c", "planar"}, {"d", "floating"}, {"e", "fixed"}};
    for (const auto& [link, type] : types) {
        links += "  <link name=\"" + link + "\"><inertial>" + kInertial + "</inertial></link>\n";
        joints += "  <joint name=\"j" + link + "\" type=\"" + type + "\"><parent link=\"" +
                  (link == "e" ? std::string("a") : std::string("base")) + "\"/><child link=\"" + link +
                  "\"/><axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint>\n";
    }
    const fs::path file = write_file("types.urdf", "<robot name=\"types\">\n  <link name=\"base\"/>\n" + links + joints + "</robot>\n");
    const CommandResult check = run_mbd("check " + file.string());
    ASSERT_EQ(check.exit_code, 0) << check.err;
    EXPECT_NE(check.out.find("bodies (4):"), std::string::npos) << check.out;
    EXPECT_NE(check.out.find("degrees of freedom (rank of C_q): 11"), std::string::npos) << check.out;
    for (const char* mapped : {"ja +revolute", "jb +prismatic", "jc +planar"})
        EXPECT_TRUE(std::regex_search(check.out, std::regex(mapped))) << mapped << "\n" << check.out;
}

}  // namespace
}  // namespace mbd::test
