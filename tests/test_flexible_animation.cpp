// The animation of a flexible body (`mbd animate`, issue 40): the HTML page draws an ANCF cable
// as a tube through its nodes (viewer.js placeFlexible), from node columns it holds at its
// keyframes. Oracle: the result CSV the page was made from; at every keyframe each node's
// position in the page is the CSV's row at that time, as the float32 the page stores (exactly),
// and the tube's node list names the CSV's columns of that node. The .glb export draws the body
// as a skinned tube: read back with tinygltf and skinned in the test (linear blend skinning,
// glTF 2.0 section 3.7.3), the centre of the ring of vertices bound to a node's joint is the
// CSV's node position at every frame; the file passes the Khronos validator (ctest
// viewer_gltf_validator, cable-pendulum.glb of viewer/test/make_outputs.sh).
#include "support/glb_reader.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

namespace mbd {
namespace {

namespace fs = std::filesystem;

// The page's text between the opening tag `open` and the next "</script>".
std::string script_text(const std::string& page, const std::string& open) {
    const size_t begin = page.find(open);
    if (begin == std::string::npos) return {};
    const size_t start = begin + open.size();
    return page.substr(start, page.find("</script>", start) - start);
}

// RFC 4648 base64, as the page's motion is written (html_export.cpp Base64Writer).
std::vector<unsigned char> decode_base64(const std::string& text) {
    auto value = [](char c) -> int {
        if (c >= 'A' && c <= 'Z') return c - 'A';
        if (c >= 'a' && c <= 'z') return c - 'a' + 26;
        if (c >= '0' && c <= '9') return c - '0' + 52;
        return c == '+' ? 62 : c == '/' ? 63 : -1;
    };
    std::vector<unsigned char> out;
    unsigned bits = 0;
    int count = 0;
    for (char c : text) {
        const int v = value(c);
        if (v < 0) continue;  // padding, white space
        bits = (bits << 6) | static_cast<unsigned>(v);
        count += 6;
        if (count >= 8) {
            count -= 8;
            out.push_back(static_cast<unsigned char>((bits >> count) & 0xff));
        }
    }
    return out;
}

// A four-element cable pinned at one end, released horizontal (both the page's and the .glb's tests)
const char* const kCablePendulum =
    "dimension: planar\ngravity: [0, -9.81]\nflexible_bodies:\n"
    "  - {name: rope, type: ancf_cable, from: [0, 0], to: [1, 0], elements: 4, modulus: 1.0e4, area: 1.0, "
    "second_moment: 1.0e-3, density: 1.0}\n"
    "joints:\n  - {name: pin, type: revolute, bodies: [ground, {body: rope, node: 0}]}\n";

template <class T>
T read_at(const std::vector<unsigned char>& bytes, size_t offset) {
    T x;
    std::memcpy(&x, bytes.data() + offset, sizeof x);
    return x;
}

TEST(FlexibleAnimation, ThePageDrawsTheCableThroughTheNodesOfTheResultAtEveryKeyframe) {
    const fs::path dir = test::scratch("flexible_animation");
    const fs::path scene = test::write_text(
        dir / "cable-pendulum.yaml",
        kCablePendulum);
    const fs::path csv = dir / "motion.csv", page = dir / "motion.html";
    const test::CommandResult run =
        test::run_mbd("simulate '" + scene.string() + "' --t-end 0.5 --output-step 0.01 -q -o '" + csv.string() + "'");
    ASSERT_EQ(run.exit_code, 0) << run.err;
    const test::CommandResult animate =
        test::run_mbd("animate '" + scene.string() + "' '" + csv.string() + "' -o '" + page.string() + "'");
    ASSERT_EQ(animate.exit_code, 0) << animate.err;

    const test::Csv result = test::read_csv(csv);
    const std::string text = test::read_text(page);
    const nlohmann::json j = nlohmann::json::parse(script_text(text, "<script id=\"mbd-scene\" type=\"application/json\">"));
    const std::vector<unsigned char> motion = decode_base64(script_text(text, "<script id=\"mbd-motion\" type=\"text/plain\">"));

    ASSERT_EQ(j["flexible"].size(), 1u);
    const nlohmann::json& rope = j["flexible"][0];
    EXPECT_EQ(rope["name"], "rope");
    EXPECT_GT(rope["radius"].get<double>(), 0.0);
    ASSERT_EQ(rope["nodes"].size(), 5u);
    const size_t keyframes = j["keyframes"].get<size_t>();
    ASSERT_GE(keyframes, 2u);
    std::vector<double> times(keyframes);
    for (size_t k = 0; k < keyframes; ++k) times[k] = read_at<double>(motion, k * sizeof(double));
    EXPECT_EQ(times.front(), result.rows.front()[0]);
    EXPECT_EQ(times.back(), result.rows.back()[0]);

    size_t compared = 0;
    for (int node = 0; node < 5; ++node) {
        const nlohmann::json& columns = rope["nodes"][node];
        EXPECT_EQ(columns[2].get<int>(), -1);  // planar: no z
        for (int axis = 0; axis < 2; ++axis) {
            const int c = columns[axis].get<int>();
            const std::string name = "rope.node" + std::to_string(node) + "." + "xy"[axis];
            ASSERT_EQ(j["columns"][c]["name"], name);
            ASSERT_EQ(result.column(name), c);
            ASSERT_TRUE(j["columns"][c]["pose"].get<bool>()) << name << " is not held at the keyframes";
            const size_t offset = j["columns"][c]["offset"].get<size_t>();
            size_t row = 0;
            for (size_t k = 0; k < keyframes; ++k) {
                while (row < result.rows.size() && result.rows[row][0] != times[k]) ++row;
                ASSERT_LT(row, result.rows.size()) << "keyframe time " << times[k] << " is no row of the CSV";
                EXPECT_EQ(read_at<float>(motion, offset + k * sizeof(float)), static_cast<float>(result.rows[row][c]))
                    << name << " at t = " << times[k];
                ++compared;
            }
        }
    }
    EXPECT_EQ(compared, 10 * keyframes);
    // the cable swings: its free end falls by a sizeable part of its length within 0.5 s
    EXPECT_LT(result.rows.back()[result.column("rope.node4.y")], -0.3);
}

TEST(FlexibleAnimation, AResultWithoutTheNodeColumnsIsRefusedNamingTheColumn) {
    const fs::path dir = test::scratch("flexible_animation_refusal");
    const fs::path scene = test::write_text(
        dir / "cable.yaml",
        "dimension: planar\nflexible_bodies:\n"
        "  - {name: rope, type: ancf_cable, from: [0, 0], to: [1, 0], elements: 2, modulus: 1.0e4, area: 1.0, "
        "second_moment: 1.0e-3, density: 1.0}\n");
    const fs::path csv = test::write_text(dir / "motion.csv", "t,rope.node0.x,rope.node0.y\n0,0,0\n0.1,0,0\n");
    const fs::path page = dir / "motion.html";
    const test::CommandResult r =
        test::run_mbd("animate '" + scene.string() + "' '" + csv.string() + "' -o '" + page.string() + "'");
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    EXPECT_NE(r.err.find("rope.node1.x"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(page));
    EXPECT_FALSE(fs::exists(page.string() + ".partial"));
}

// ---------------------------------------------------------------- the .glb export's skinned tube

std::string quoted(const fs::path& p) { return "'" + p.string() + "'"; }

// The tube of `body` in the .glb, skinned at every frame: per frame, the world position of each
// vertex, sum_j w_j M_j(frame) B_j v (M_j the joint's world transform from the file's own
// samples, B_j its inverse bind matrix); and the vertices of the ring bound to each joint.
struct SkinnedTube {
    std::vector<std::vector<Eigen::Vector3d>> frames;  // [frame][vertex]
    std::vector<int> joint_nodes;                       // the skin's joints (glTF node indices)
    std::vector<int> vertex_joint;                      // the joint (index in the skin) of the largest weight
};

SkinnedTube skin_tube(const test::Glb& glb, const std::string& body, size_t frames) {
    SkinnedTube out;
    const int node = glb.node(body + "/tube");
    EXPECT_GE(node, 0) << "no tube node for " << body;
    if (node < 0) return out;
    const tinygltf::Node& tube = glb.model.nodes[node];
    EXPECT_GE(tube.skin, 0);
    const tinygltf::Skin& skin = glb.model.skins[tube.skin];
    const tinygltf::Primitive& p = glb.model.meshes[tube.mesh].primitives.at(0);
    const std::vector<float> positions = glb.floats(p.attributes.at("POSITION"));
    const std::vector<float> weights = glb.floats(p.attributes.at("WEIGHTS_0"));
    EXPECT_EQ(glb.model.accessors[p.attributes.at("JOINTS_0")].componentType, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
    const std::vector<uint16_t> joints = glb.values<uint16_t>(p.attributes.at("JOINTS_0"));
    const std::vector<float> ibm = glb.floats(skin.inverseBindMatrices);
    out.joint_nodes = skin.joints;
    const size_t vertices = positions.size() / 3;
    for (size_t v = 0; v < vertices; ++v)
        out.vertex_joint.push_back(joints[4 * v + (std::max_element(&weights[4 * v], &weights[4 * v + 4]) - &weights[4 * v])]);
    for (size_t f = 0; f < frames; ++f) {
        std::vector<Eigen::Matrix4d> m(skin.joints.size());
        for (size_t j = 0; j < skin.joints.size(); ++j) {
            Eigen::Matrix4d bind;
            for (int c = 0; c < 4; ++c)
                for (int r = 0; r < 4; ++r) bind(r, c) = ibm[16 * j + 4 * c + r];  // column-major
            m[j] = glb.world(skin.joints[j], f).matrix() * bind;
        }
        std::vector<Eigen::Vector3d> world(vertices, Eigen::Vector3d::Zero());
        for (size_t v = 0; v < vertices; ++v)
            for (int k = 0; k < 4; ++k)
                if (weights[4 * v + k] != 0.0f)
                    world[v] += weights[4 * v + k] *
                                (m[joints[4 * v + k]] *
                                 Eigen::Vector4d(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2], 1.0))
                                    .head<3>();
        out.frames.push_back(std::move(world));
    }
    return out;
}

// The CSV's node k of `body` at `row` (planar: z = 0).
Eigen::Vector3d csv_node(const test::Csv& csv, const std::string& body, int k, size_t row, bool planar) {
    const std::string n = body + ".node" + std::to_string(k) + ".";
    return {csv.rows[row][csv.column(n + "x")], csv.rows[row][csv.column(n + "y")],
            planar ? 0.0 : csv.rows[row][csv.column(n + "z")]};
}

// At every frame and node, the centre of the ring bound to the node's joint against the CSV's
// node; the ring's vertices all at one distance (the radius) from it. Returns the largest
// centre error and sets `radius`, `largest_z` (|z| of any vertex).
double tube_against_csv(const test::Glb& glb, const test::Csv& csv, const std::string& body, int nodes, bool planar,
                        double& radius, double& largest_z, double& centre_z) {
    const SkinnedTube tube = skin_tube(glb, body, csv.rows.size());
    const auto [times, unused] = glb.channel(glb.node(body + "/node0"), "translation");
    EXPECT_EQ(times.size(), csv.rows.size());
    double worst = 0.0;
    radius = -1.0, largest_z = 0.0, centre_z = 0.0;
    for (size_t f = 0; f < tube.frames.size(); ++f) {
        EXPECT_EQ(times[f], static_cast<float>(csv.rows[f][0]));
        for (const Eigen::Vector3d& v : tube.frames[f]) largest_z = std::max(largest_z, std::abs(v.z()));
        for (int k = 0; k < nodes; ++k) {
            const int joint = static_cast<int>(std::find(tube.joint_nodes.begin(), tube.joint_nodes.end(),
                                                         glb.node(body + "/node" + std::to_string(k))) -
                                               tube.joint_nodes.begin());
            EXPECT_LT(joint, static_cast<int>(tube.joint_nodes.size())) << body << " node " << k << " is no joint";
            Eigen::Vector3d centre = Eigen::Vector3d::Zero();
            std::vector<Eigen::Vector3d> ring;
            for (size_t v = 0; v < tube.vertex_joint.size(); ++v)
                if (tube.vertex_joint[v] == joint) ring.push_back(tube.frames[f][v]);
            EXPECT_GE(ring.size(), 3u);
            for (const Eigen::Vector3d& v : ring) centre += v / double(ring.size());
            worst = std::max(worst, (centre - csv_node(csv, body, k, f, planar)).norm());
            centre_z = std::max(centre_z, std::abs(centre.z()));
            for (const Eigen::Vector3d& v : ring) {
                if (radius < 0) radius = (v - centre).norm();
                EXPECT_NEAR((v - centre).norm(), radius, 1e-5 * radius) << "ring of node " << k << " at frame " << f;
            }
        }
    }
    return worst;
}

TEST(FlexibleGlb, ThePlanarCablesTubeIsAtTheCsvsNodesAtEveryFrameAndInItsPlane) {
    const fs::path dir = test::scratch("flexible_glb_planar");
    const fs::path scene = test::write_text(
        dir / "cable-pendulum.yaml",
        kCablePendulum);
    const test::CommandResult run = test::run_mbd("simulate " + quoted(scene) + " --t-end 0.5 --output-step 0.02 -q -o " +
                                                  quoted(dir / "r.csv") + " --animation " + quoted(dir / "r.glb"));
    ASSERT_EQ(run.exit_code, 0) << run.err;
    const test::Csv csv = test::read_csv(dir / "r.csv");
    const test::Glb glb = test::load_glb(dir / "r.glb");
    double radius = 0, largest_z = 0, centre_z = 0;
    const double worst = tube_against_csv(glb, csv, "rope", 5, true, radius, largest_z, centre_z);
    std::printf("planar cable, %zu frames: tube centre to CSV node %.3g m, radius %.4g m, largest |z| %.4g m, "
                "centres' |z| %.3g m\n", csv.rows.size(), worst, radius, largest_z, centre_z);
    EXPECT_LT(worst, 2e-6);  // float32 positions and matrices of a 1 m cable
    EXPECT_GT(radius, 0.0);
    EXPECT_LT(centre_z, 1e-6);                    // the centreline in the x-y plane
    EXPECT_LE(largest_z, radius * (1.0 + 1e-5));  // the tube no thicker than its radius across it
    // the cable has bent and fallen: the free end's ring is far from where it was bound
    EXPECT_LT(csv.rows.back()[csv.column("rope.node4.y")], -0.3);
}

TEST(FlexibleGlb, ASpatialCableWithARigidBallKeepsTheBallsAnimationAndFollowsTheNodes) {
    const fs::path dir = test::scratch("flexible_glb_spatial");
    const fs::path scene = test::write_text(
        dir / "cable-ball.yaml",
        "dimension: spatial\ngravity: [0, 0, -9.81]\nflexible_bodies:\n"
        "  - {name: rope, type: ancf_cable, from: [0, 0, 0], to: [0.8, 0.6, 0], elements: 3, modulus: 1.0e4, "
        "area: 1.0, second_moment: 1.0e-3, density: 1.0}\n"
        "bodies:\n  - {name: ball, mass: 0.5, inertia: [1.0e-3, 1.0e-3, 1.0e-3], position: [0.8, 0.6, 0], "
        "angular_velocity: [0, 0, 3]}\n"
        "joints:\n"
        "  - {name: pin, type: spherical, bodies: [ground, {body: rope, node: 0}], point: [0, 0, 0]}\n"
        "  - {name: tip, type: spherical, bodies: [{body: rope, node: 3}, ball], point: [0.8, 0.6, 0]}\n");
    const test::CommandResult run = test::run_mbd("simulate " + quoted(scene) + " --t-end 0.4 --output-step 0.02 -q -o " +
                                                  quoted(dir / "r.csv") + " --animation " + quoted(dir / "r.glb"));
    ASSERT_EQ(run.exit_code, 0) << run.err;
    const test::Csv csv = test::read_csv(dir / "r.csv");
    const test::Glb glb = test::load_glb(dir / "r.glb");
    double radius = 0, largest_z = 0, centre_z = 0;
    const double worst = tube_against_csv(glb, csv, "rope", 4, false, radius, largest_z, centre_z);
    // the rigid ball: its node's world pose at every frame is the CSV's (position, Euler parameters up to sign)
    const int ball = glb.node("ball");
    ASSERT_GE(ball, 0);
    double ball_worst = 0.0;
    const int x = csv.column("ball.x"), e0 = csv.column("ball.e0");
    for (size_t f = 0; f < csv.rows.size(); ++f) {
        const Eigen::Affine3d m = glb.world(ball, f);
        const std::vector<double>& row = csv.rows[f];
        ball_worst = std::max(ball_worst, (m.translation() - Eigen::Vector3d(row[x], row[x + 1], row[x + 2])).norm());
        const Eigen::Quaterniond q(row[e0], row[e0 + 1], row[e0 + 2], row[e0 + 3]);
        ball_worst = std::max(ball_worst, (m.rotation() - q.normalized().toRotationMatrix()).norm());
    }
    std::printf("spatial cable with a ball, %zu frames: tube centre to CSV node %.3g m (radius %.4g m), ball pose %.3g\n",
                csv.rows.size(), worst, radius, ball_worst);
    EXPECT_LT(worst, 2e-6);
    EXPECT_LT(ball_worst, 2e-6);
    EXPECT_LT(csv.rows.back()[x + 2], -0.2);  // it has fallen: the frames differ from the bind pose
}

TEST(FlexibleGlb, TheEquilibriumOfAFloatingFrameBodyIsDrawnThroughItsNodes) {
    // an ffrf_body's CSV has its frame's columns (blade.x, blade.y, blade.angle) beside its
    // nodes': `mbd statics --animation` once refused them as naming no body
    const fs::path dir = test::scratch("flexible_glb_ffrf");
    const fs::path scene = test::write_text(
        dir / "cantilever.yaml",
        "dimension: planar\ngravity: [0, -1]\nflexible_bodies:\n"
        "  - {name: blade, type: ffrf_body, from: [0, 0], to: [1, 0], elements: 8, modes: 2, modulus: 1.0e6, "
        "area: 1.0, second_moment: 1.0e-6, density: 1.0}\n"
        "joints:\n  - {name: clamp, type: fixed, bodies: [ground, {body: blade, at: 0}]}\n");
    const test::CommandResult r =
        test::run_mbd("statics " + quoted(scene) + " --json --animation " + quoted(dir / "r.glb"));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const nlohmann::json nodes = nlohmann::json::parse(r.out)["flexible_bodies"]["blade"]["nodes"];
    ASSERT_EQ(nodes.size(), 9u);
    const test::Glb glb = test::load_glb(dir / "r.glb");
    const SkinnedTube tube = skin_tube(glb, "blade", 1);
    ASSERT_EQ(tube.frames.size(), 1u);
    double worst = 0.0;
    for (size_t k = 0; k < nodes.size(); ++k) {
        const int joint = static_cast<int>(std::find(tube.joint_nodes.begin(), tube.joint_nodes.end(),
                                                     glb.node("blade/node" + std::to_string(k))) -
                                           tube.joint_nodes.begin());
        Eigen::Vector3d centre = Eigen::Vector3d::Zero();
        int count = 0;
        for (size_t v = 0; v < tube.vertex_joint.size(); ++v)
            if (tube.vertex_joint[v] == joint) centre += tube.frames[0][v], ++count;
        ASSERT_GT(count, 0) << "node " << k;
        centre /= count;
        worst = std::max(worst, (centre - Eigen::Vector3d(nodes[k][0], nodes[k][1], 0.0)).norm());
    }
    std::printf("ffrf cantilever at rest: tube centres to the report's nodes %.3g m (tip y %.6f)\n", worst,
                nodes.back()[1].get<double>());
    EXPECT_LT(nodes.back()[1].get<double>(), -0.1);  // bent: w L^4 / (8 EI) = 0.125 m
    EXPECT_LT(worst, 1e-6);
    const test::CommandResult page = test::run_mbd("statics " + quoted(scene) + " --animation " + quoted(dir / "r.html"));
    EXPECT_EQ(page.exit_code, 0) << page.err;
}

}  // namespace
}  // namespace mbd
