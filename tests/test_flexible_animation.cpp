// The animation of a flexible body (`mbd animate`, issue 40): the HTML page draws an ANCF cable
// as a tube through its nodes (viewer.js placeFlexible), from node columns it holds at its
// keyframes. Oracle: the result CSV the page was made from; at every keyframe each node's
// position in the page is the CSV's row at that time, as the float32 the page stores (exactly),
// and the tube's node list names the CSV's columns of that node.
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

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
        "dimension: planar\ngravity: [0, -9.81]\nflexible_bodies:\n"
        "  - {name: rope, type: ancf_cable, from: [0, 0], to: [1, 0], elements: 4, modulus: 1.0e4, area: 1.0, "
        "second_moment: 1.0e-3, density: 1.0}\n"
        "joints:\n  - {name: pin, type: revolute, bodies: [ground, {body: rope, node: 0}]}\n");
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

}  // namespace
}  // namespace mbd
