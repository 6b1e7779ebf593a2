// The JSON outputs (app/include/mbd/app/json_output.hpp): `mbd simulate --json` and `mbd statics
// --json` on a scene whose folder name holds a double quote and a backslash print JSON that
// parses, and the values read back equal oracles that do not come from mbd (the path itself,
// the row count of the output grid, the closed-form equilibrium of the torqued pendulum); a
// non-finite number is written as null and listed under "non_finite" (RFC 6901 pointers).
#include <mbd/app/json_output.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <string>

#include "support/test_support.hpp"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// One shell word for any path (single quotes; a single quote inside closed, escaped, reopened).
std::string shell_word(const fs::path& p) {
    std::string out = "'";
    for (char c : p.string()) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

// A copy of a shipped scene in a folder named  say "hi" \ there  (quote and backslash).
fs::path awkward_copy(const std::string& relative) {
    const fs::path dir = mbd::test::scratch("json") / "say \"hi\" \\ there";
    fs::create_directories(dir);
    const fs::path copy = dir / fs::path(relative).filename();
    fs::copy_file(mbd::test::scene_path(relative), copy, fs::copy_options::overwrite_existing);
    return copy;
}

TEST(JsonOutput, SimulateJsonParsesWithAQuoteAndABackslashInThePath) {
    const fs::path scene = awkward_copy("dynamics/pendulum-a01.yaml");
    const fs::path csv = scene.parent_path() / "out.csv";
    const auto r = mbd::test::run_mbd("simulate " + shell_word(scene) + " --t-end 0.5 --output-step 0.1 --json -q -o " +
                                      shell_word(csv));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    json summary;
    ASSERT_NO_THROW(summary = json::parse(r.out)) << r.out;
    // the path, quote and backslash included, reads back exactly as given
    EXPECT_EQ(summary.at("scene").get<std::string>(), scene.string());
    // t = 0, 0.1, ..., 0.5: six rows, as many as the CSV holds
    EXPECT_EQ(summary.at("rows").get<long>(), 6);
    EXPECT_EQ(static_cast<long>(mbd::test::read_csv(csv).rows.size()), 6);
    EXPECT_DOUBLE_EQ(summary.at("t_end").get<double>(), 0.5);
    EXPECT_TRUE(summary.at("position_violation").is_number()) << r.out;
    EXPECT_FALSE(summary.contains("non_finite")) << r.out;
}

TEST(JsonOutput, StaticsJsonParsesAndGivesTheClosedFormEquilibrium) {
    const fs::path scene = awkward_copy("statics/pendulum-torque.yaml");
    const auto r = mbd::test::run_mbd("statics " + shell_word(scene) + " --json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    json report;
    ASSERT_NO_THROW(report = json::parse(r.out)) << r.out;
    ASSERT_TRUE(report.at("converged").get<bool>()) << r.out;
    // The pin is at the origin; the scene places the mass centre at R0 = (0.460530, -0.194709)
    // with the body angle -0.4, so l = |R0| and the line pin -> centre sits delta = atan2(R0) + 0.4
    // from the body's x axis. Equilibrium of moments about the pin: m g l cos(phi) = M (m = 1,
    // g = 9.81, M = 2), phi the line's angle; the stable root hangs below the pin, phi < 0.
    const double m = 1.0, g = 9.81, M = 2.0, x0 = 0.460530, y0 = -0.194709;
    const double l = std::hypot(x0, y0), delta = std::atan2(y0, x0) + 0.4, phi = -std::acos(M / (m * g * l));
    const json& rod = report.at("bodies").at("rod");
    EXPECT_NEAR(rod.at("angle").get<double>(), phi - delta, 1e-9) << r.out;
    EXPECT_NEAR(rod.at("x").get<double>(), l * std::cos(phi), 1e-9);
    EXPECT_NEAR(rod.at("y").get<double>(), l * std::sin(phi), 1e-9);
    // the pin carries the weight: reaction on the rod (m g upward, no horizontal force)
    const json& pin = report.at("reactions").at("pin");
    EXPECT_NEAR(pin.at("fx").get<double>(), 0.0, 1e-9);
    EXPECT_NEAR(pin.at("fy").get<double>(), m * g, 1e-9);
    EXPECT_EQ(report.at("stability").get<std::string>(), "stable");
}

TEST(JsonOutput, NonFiniteNumbersAreNullAndListedByPointer) {
    mbd::Json doc;
    doc["a"] = NAN;
    doc["b"]["c/d~e"] = INFINITY;
    doc["list"] = mbd::Json::array({1.5, -INFINITY});
    doc["fine"] = 2.0;
    const json back = json::parse(mbd::json_text(doc));
    EXPECT_TRUE(back.at("a").is_null());
    EXPECT_TRUE(back.at("b").at("c/d~e").is_null());
    EXPECT_TRUE(back.at("list").at(1).is_null());
    EXPECT_EQ(back.at("list").at(0).get<double>(), 1.5);
    EXPECT_EQ(back.at("fine").get<double>(), 2.0);
    // RFC 6901: '/' in a key is "~1", '~' is "~0"
    EXPECT_EQ(back.at("non_finite"), json::array({"/a", "/b/c~1d~0e", "/list/1"}));
    // and each pointer finds its null
    for (const auto& pointer : back.at("non_finite")) EXPECT_TRUE(back.at(json::json_pointer(pointer.get<std::string>())).is_null());
    // all finite: no "non_finite" key
    EXPECT_FALSE(json::parse(mbd::json_text({{"x", 1.0}})).contains("non_finite"));
}

}  // namespace
