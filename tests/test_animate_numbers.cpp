// `mbd animate` never writes a number that is not finite (issue 42): a CSV cell beyond the
// 32-bit float range that glTF and the page store (1e39, +-1e308) is refused naming the file,
// its line and the column; so is an STL mesh with a NaN vertex (naming the mesh and the
// vertex) and a CSV cut inside its last line (naming that line). No output file is left.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "support/test_support.hpp"

namespace {

namespace fs = std::filesystem;
using mbd::test::write_text;
using mbd::test::read_text;
using mbd::test::run_mbd;
using mbd::test::scratch;

std::string pendulum_scene() { return mbd::test::scene_path("dynamics/pendulum-a01.yaml").string(); }

// The pendulum's motion for 0.1 s, 11 rows (t, bob.x, bob.y, bob.angle, bob.vx, bob.vy, bob.omega).
std::string pendulum_csv(const fs::path& dir) {
    const fs::path csv = dir / "motion.csv";
    const auto r = run_mbd("simulate " + pendulum_scene() + " --t-end 0.1 --output-step 0.01 -q -o " + csv.string());
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return read_text(csv);
}

// `text` with the cell of (file) line `line`, column `column` (1-based) replaced by `cell`.
std::string with_cell(const std::string& text, int line, int column, const std::string& cell) {
    std::vector<std::string> lines;
    std::string current;
    for (char c : text) {
        if (c == '\n') lines.push_back(current), current.clear();
        else current += c;
    }
    std::string& row = lines.at(static_cast<std::size_t>(line - 1));
    std::size_t begin = 0;
    for (int k = 1; k < column; ++k) begin = row.find(',', begin) + 1;
    const std::size_t end = row.find(',', begin);
    row.replace(begin, end == std::string::npos ? std::string::npos : end - begin, cell);
    std::string out;
    for (const std::string& l : lines) out += l + '\n';
    return out;
}

// Runs `mbd animate` and expects a refusal (exit 2) whose message holds every one of `words`,
// with neither the output nor its .partial left.
void expect_refused(const std::string& scene, const fs::path& csv, const fs::path& output,
                    const std::vector<std::string>& words) {
    const auto r = run_mbd("animate " + scene + " " + csv.string() + " -o " + output.string());
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    for (const std::string& w : words) EXPECT_NE(r.err.find(w), std::string::npos) << "'" << w << "' in: " << r.err;
    EXPECT_FALSE(fs::exists(output));
    EXPECT_FALSE(fs::exists(output.string() + ".partial"));
}

TEST(AnimateNumbers, CellsBeyondTheFloatRangeAreRefusedNamingLineAndColumn) {
    const fs::path dir = scratch("animate-range");
    const std::string good = pendulum_csv(dir);
    // the unchanged result animates: the refusals below are the numbers' doing
    auto r = run_mbd("animate " + pendulum_scene() + " " + (dir / "motion.csv").string() + " -o " +
                     (dir / "good.glb").string());
    ASSERT_EQ(r.exit_code, 0) << r.err;

    // 1e39 in bob.x (column 2) of the fourth line: once inf in the .glb; +-1e308 once -nan in the page
    const fs::path big = write_text(dir / "big.csv", with_cell(good, 4, 2, "1e39"));
    expect_refused(pendulum_scene(), big, dir / "big.glb", {big.string() + ":4:", "column 2 'bob.x'", "'1e39'", "3.4e38"});
    expect_refused(pendulum_scene(), big, dir / "big.html", {big.string() + ":4:", "'bob.x'"});
    const fs::path huge = write_text(dir / "huge.csv", with_cell(with_cell(good, 6, 3, "1e308"), 7, 3, "-1e308"));
    expect_refused(pendulum_scene(), huge, dir / "huge.html", {huge.string() + ":6:", "column 3 'bob.y'", "'1e308'"});
    expect_refused(pendulum_scene(), huge, dir / "huge.glb", {huge.string() + ":6:", "'bob.y'"});
    // the largest float itself is still a number the files can hold
    const fs::path edge = write_text(dir / "edge.csv", with_cell(good, 4, 5, "3.4e38"));
    r = run_mbd("animate " + pendulum_scene() + " " + edge.string() + " -o " + (dir / "edge.html").string());
    EXPECT_EQ(r.exit_code, 0) << r.err;
}

TEST(AnimateNumbers, CsvCutInsideItsLastLineIsRefused) {
    const fs::path dir = scratch("animate-cut");
    const std::string good = pendulum_csv(dir);
    // 12 lines: the header and 11 rows; cut two characters off the last number
    const fs::path cut = write_text(dir / "cut.csv", good.substr(0, good.size() - 3));
    expect_refused(pendulum_scene(), cut, dir / "cut.glb", {cut.string() + ":12:", "no line end"});
    // a last line cut before its last cells: the short row is named
    const std::string shorter = good.substr(0, good.rfind(',', good.size() - 2)) + "\n";
    const fs::path few = write_text(dir / "few.csv", shorter);
    expect_refused(pendulum_scene(), few, dir / "few.html", {few.string() + ":12:", "6 values for the 7 columns"});
}

// A binary STL of one triangle whose first vertex's x is `x`.
std::string binary_stl(float x) {
    std::string out(80, ' ');
    const std::uint32_t count = 1;
    out.append(reinterpret_cast<const char*>(&count), 4);
    const float values[12] = {0, 0, 1, x, 0, 0, 1, 0, 0, 0, 1, 0};
    out.append(reinterpret_cast<const char*>(values), sizeof values);
    out.append(2, '\0');
    return out;
}

TEST(AnimateNumbers, MeshWithANanVertexIsRefusedNamingTheFile) {
    const fs::path dir = scratch("animate-mesh");
    const std::string good = pendulum_csv(dir);
    write_text(dir / "motion.csv", good);
    const std::string scene_text = read_text(pendulum_scene());
    const std::string visual = "mass: 1.0, inertia: 1.0e-6, position: [1.0, 0.0], angle: 0.0,\n"
                               "     visual: [{shape: mesh, file: bob.stl, scale: 0.1}]";
    const fs::path scene = write_text(dir / "scene.yaml", mbd::test::replaced(scene_text, "mass: 1.0, inertia: 1.0e-6, "
                                                                                    "position: [1.0, 0.0], angle: 0.0",
                                                                         visual));
    write_text(dir / "bob.stl", binary_stl(0.5f));
    auto r = run_mbd("animate " + scene.string() + " " + (dir / "motion.csv").string() + " -o " + (dir / "ok.glb").string());
    ASSERT_EQ(r.exit_code, 0) << "the finite mesh animates: " << r.err;

    write_text(dir / "bob.stl", binary_stl(std::numeric_limits<float>::quiet_NaN()));
    for (const char* output : {"nan.glb", "nan.html"})
        expect_refused(scene.string(), dir / "motion.csv", dir / output,
                       {"bob.stl", "has a vertex that is not a finite number", "nan"});
}

}  // namespace
