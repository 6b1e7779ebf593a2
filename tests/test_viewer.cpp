// Issue 15, the animation export: the `visual:` key and its errors, the shapes derived from
// a scene (checked against the book's four-bar link lengths), the tessellated shapes
// (closed-form radii and volumes), the glTF binary read back with tinygltf against the
// CSV it came from (every sample within 1e-6), and bad input (a missing mesh, an unknown
// shape, a CSV of another scene) failing with file:line and no output file.
// The browser viewer and the Khronos validator are tested by viewer/test/ (ctest viewer_*).
#include <mbd/viewer/animation_export.hpp>
#include <mbd/viewer/keyframes.hpp>
#include <mbd/viewer/shape_mesh.hpp>
#include <mbd/visual.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <fstream>
#include <sstream>
#include <map>

#include "support/glb_reader.hpp"
#include "support/test_support.hpp"

namespace {

namespace fs = std::filesystem;
using mbd::test::write_text;
using mbd::Vec3;
using mbd::test::Csv;
using mbd::test::read_csv;
using mbd::test::run_mbd;
using mbd::test::scratch;
using mbd::test::Glb;
using mbd::test::load_glb;

constexpr double kPi = 3.14159265358979323846;

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

std::string quoted(const fs::path& p) { return "'" + p.string() + "'"; }
std::string scene_file(const std::string& relative) { return quoted(mbd::test::scene_path(relative)); }

// Signed volume enclosed by a closed triangle mesh (divergence theorem).
double enclosed_volume(const mbd::viewer::TriangleMesh& m) {
    double v = 0.0;
    for (size_t t = 0; t < m.indices.size(); t += 3) {
        Vec3 p[3];
        for (int k = 0; k < 3; ++k)
            p[k] = Vec3(m.positions[3 * m.indices[t + k]], m.positions[3 * m.indices[t + k] + 1],
                        m.positions[3 * m.indices[t + k] + 2]);
        v += p[0].dot(p[1].cross(p[2])) / 6.0;
    }
    return v;
}

TEST(Visual, ShapesOfTheVisualKeyWithPoseScaleAndColour) {
    const mbd::Model model = mbd::test::load("examples/visual-shapes.yaml");
    const auto& arm = model.bodies[0].visuals;
    ASSERT_EQ(arm.size(), 3u);
    EXPECT_EQ(arm[0].kind, mbd::ShapeKind::Box);
    EXPECT_TRUE(arm[0].size.isApprox(Vec3(0.04, 0.04, 0.4)));
    EXPECT_TRUE(arm[0].color.isApprox(Vec3(0x3b, 0x73, 0xc4) / 255.0));  // "#3b73c4"
    EXPECT_EQ(arm[1].kind, mbd::ShapeKind::Cylinder);
    EXPECT_TRUE((arm[1].rotation * Vec3::UnitZ()).isApprox(Vec3::UnitX(), 1e-12));  // 90 degrees about y
    EXPECT_TRUE(arm[1].position.isApprox(Vec3(0, 0, 0.2)));
    EXPECT_EQ(arm[2].kind, mbd::ShapeKind::Capsule);
    const auto& bob = model.bodies[1].visuals;
    ASSERT_EQ(bob.size(), 2u);
    EXPECT_EQ(bob[1].kind, mbd::ShapeKind::Mesh);
    EXPECT_TRUE(fs::exists(bob[1].mesh_file)) << bob[1].mesh_file;
    EXPECT_TRUE(bob[1].scale.isApprox(Vec3::Constant(0.8)));
}

// The four-bar of Table 3.2: links l2 = 0.2, l3 = 0.4, l4 = 0.5 m between their joints.
TEST(Visual, DerivedLinksJoinEachBodysJointPoints) {
    const mbd::Model model = mbd::test::load("four-bar.yaml");
    const mbd::VisualScene scene = mbd::build_visual_scene(model);
    const double lengths[] = {0.2, 0.4, 0.5};
    for (int b = 0; b < 3; ++b) {
        double link = 0.0;  // the link: the cylinder through the mass centre
        bool sphere_at_centre = false;
        for (const auto& s : scene.bodies[b]) {
            if (s.kind == mbd::ShapeKind::Cylinder && s.position.norm() < 1e-6) link = std::max(link, s.length);
            if (s.kind == mbd::ShapeKind::Sphere && s.position.norm() == 0.0) sphere_at_centre = true;
        }
        EXPECT_NEAR(link, lengths[b], 1e-6) << model.bodies[b].name;
        EXPECT_TRUE(sphere_at_centre) << model.bodies[b].name;
    }
    // joints O and C on the ground: two pins fixed in world at (0, 0) and (0.4, 0)
    ASSERT_EQ(scene.ground.size(), 2u);
    EXPECT_NEAR(scene.ground[0].position.norm(), 0.0, 1e-12);
    EXPECT_TRUE(scene.ground[1].position.isApprox(Vec3(0.4, 0, 0)));
    // the spring from crank (0.03, 0) to rocker (-0.05, 0), each in its body frame
    ASSERT_EQ(scene.connectors.size(), 1u);
    EXPECT_EQ(scene.connectors[0].body_a, 0);
    EXPECT_EQ(scene.connectors[0].body_b, 2);
    EXPECT_TRUE(scene.connectors[0].point_a.isApprox(Vec3(0.03, 0, 0)));
    EXPECT_TRUE(scene.connectors[0].point_b.isApprox(Vec3(-0.05, 0, 0)));
    EXPECT_TRUE(scene.up.isApprox(Vec3::UnitY()));  // against g = (0, -9.81)
}

// A body with no joint points (the torque-free body) is drawn as the uniform box of its
// inertia: I_x = m (b^2 + c^2) / 12 and its permutations give the edges back.
TEST(Visual, FreeBodyGetsItsInertiaBox) {
    const mbd::Model model = mbd::test::scene(R"(
dimension: spatial
bodies:
  - {name: brick, mass: 12, inertia: [13, 10, 5]}
)");
    const mbd::VisualScene scene = mbd::build_visual_scene(model);
    const mbd::VisualShape* box = nullptr;
    for (const auto& s : scene.bodies[0])
        if (s.kind == mbd::ShapeKind::Box) box = &s;
    ASSERT_NE(box, nullptr);
    // edges a, b, c with m (b^2 + c^2) / 12 = 13, m (a^2 + c^2) / 12 = 10, m (a^2 + b^2) / 12 = 5:
    // a^2 = 1, b^2 = 4, c^2 = 9
    const Vec3 world_edges = (box->rotation * box->size.asDiagonal()).cwiseAbs().rowwise().sum();
    EXPECT_NEAR(world_edges.x(), 1.0, 1e-9);
    EXPECT_NEAR(world_edges.y(), 2.0, 1e-9);
    EXPECT_NEAR(world_edges.z(), 3.0, 1e-9);
}

// A table of columns t, then f_k(t) for each function, at `rows` equally spaced times.
mbd::viewer::MotionTable sampled(const std::vector<std::function<double(double)>>& f, int rows, double dt) {
    mbd::viewer::MotionTable table;
    table.columns.push_back("t");
    for (size_t k = 0; k < f.size(); ++k) table.columns.push_back("f" + std::to_string(k));
    for (int r = 0; r < rows; ++r) {
        table.values.push_back(r * dt);
        for (const auto& g : f) table.values.push_back(g(r * dt));
    }
    return table;
}

// The largest distance, over every row, between a column and the straight lines
// through its kept rows.
double worst_interpolation_error(const mbd::viewer::MotionTable& table, int column, const std::vector<size_t>& kept) {
    double worst = 0.0;
    for (size_t s = 0; s + 1 < kept.size(); ++s) {
        const size_t a = kept[s], b = kept[s + 1];
        for (size_t r = a; r <= b; ++r) {
            const double f = (table.at(r, 0) - table.at(a, 0)) / (table.at(b, 0) - table.at(a, 0));
            const double line = table.at(a, column) + f * (table.at(b, column) - table.at(a, column));
            worst = std::max(worst, std::abs(line - table.at(r, column)));
        }
    }
    return worst;
}

// The reader parses blocks of rows in parallel; wherever a fault lies relative to the
// blocks, the message must name the fault's line, and the first fault in the file wins.
TEST(MotionCsv, ParallelBlocksReadTheSameTableAndNameTheFirstFaultyLine) {
    const fs::path dir = scratch("motion-csv");
    const int rows = 40;
    auto row_text = [](int r) {
        char b[64];
        std::snprintf(b, sizeof b, "%.3f,%.3f,%.3f\n", 0.1 * r, std::sin(0.1 * r), 1.0 + r);
        return std::string(b);
    };
    auto write_csv = [&](const std::string& name, const std::map<int, std::string>& replaced) {
        std::string text = "t,b.x,b.y\n";
        for (int r = 0; r < rows; ++r) text += replaced.count(r) ? replaced.at(r) : row_text(r);
        std::ofstream(dir / name) << text;
        return dir / name;
    };
    const fs::path good = write_csv("good.csv", {});
    const auto serial = mbd::viewer::read_motion_csv(good, 1);
    ASSERT_EQ(serial.rows(), static_cast<size_t>(rows));
    EXPECT_DOUBLE_EQ(serial.at(17, 1), std::round(std::sin(1.7) * 1000) / 1000);
    for (unsigned threads : {2u, 3u, 7u, 64u}) {
        const auto parallel = mbd::viewer::read_motion_csv(good, threads);
        EXPECT_TRUE(std::equal(parallel.values.begin(), parallel.values.end(), serial.values.begin(),
                               serial.values.end()))
            << threads << " blocks";
    }
    auto message = [](const fs::path& file, unsigned threads) -> std::string {
        try {
            mbd::viewer::read_motion_csv(file, threads);
        } catch (const mbd::InputError& e) {
            return e.what();
        }
        return "no error";
    };
    for (int r = 1; r < rows; ++r) {
        const std::string line = ":" + std::to_string(r + 2);  // the header is line 1
        const std::map<std::string, std::map<int, std::string>> faults = {
            {"a cell that is not a number", {{r, "0.1,abc,1\n"}}},
            {"a short row", {{r, "0.1,0.2\n"}}},
            {"a time that does not increase", {{r, row_text(r - 1)}}},
            {"two faults, the first at this row", {{r, "x,1,1\n"}, {std::min(r + 5, rows - 1), "0.1,0.2\n"}}},
        };
        for (const auto& [what, replaced] : faults) {
            if (what.rfind("two", 0) == 0 && r + 5 >= rows) continue;
            const fs::path file = write_csv("fault.csv", replaced);
            const std::string expected = message(file, 1);
            EXPECT_NE(expected.find(file.string() + line + ":"), std::string::npos) << what << ": " << expected;
            for (unsigned threads : {2u, 3u, 7u}) EXPECT_EQ(message(file, threads), expected) << what << ", " << threads << " blocks";
        }
    }
}

TEST(Keyframes, APiecewiseLinearMotionKeepsItsCornersOnly) {
    // |t - 0.3| has its corner at row 30, 0.5 - |t - 0.7| at row 70
    const auto table = sampled({[](double t) { return std::abs(t - 0.3); }, [](double t) { return 0.5 - std::abs(t - 0.7); }},
                               101, 0.01);
    EXPECT_EQ(mbd::viewer::keyframe_rows(table, {{1, 1e-9}}), (std::vector<size_t>{0, 30, 100}));
    EXPECT_EQ(mbd::viewer::keyframe_rows(table, {{2, 1e-9}}), (std::vector<size_t>{0, 70, 100}));
    EXPECT_EQ(mbd::viewer::keyframe_rows(table, {{1, 1e-9}, {2, 1e-9}}), (std::vector<size_t>{0, 30, 70, 100}));
}

TEST(Keyframes, ASmoothMotionIsDrawnWithinTheToleranceFromFewRows) {
    // x = A sin(w t): linear interpolation over h errs by at most h^2 A w^2 / 8, so every
    // segment up to h* = sqrt(8 e / (A w^2)) is admissible and the greedy choice keeps at
    // most T / (h* - dt) + 2 rows
    const double a = 3.0, w = 2.0, dt = 1e-3, e = 1e-4 * a;
    const int rows = 10001;
    const auto table = sampled({[&](double t) { return a * std::sin(w * t); }, [&](double t) { return a * std::cos(w * t); }},
                               rows, dt);
    const std::vector<size_t> kept = mbd::viewer::keyframe_rows(table, {{1, e}, {2, e}});
    EXPECT_EQ(kept.front(), 0u);
    EXPECT_EQ(kept.back(), static_cast<size_t>(rows - 1));
    EXPECT_LE(worst_interpolation_error(table, 1, kept), e);
    EXPECT_LE(worst_interpolation_error(table, 2, kept), e);
    const double h = std::sqrt(8 * e / (a * w * w));
    EXPECT_LE(kept.size(), static_cast<size_t>((rows - 1) * dt / (h - dt)) + 2) << kept.size() << " rows kept";
    EXPECT_LT(kept.size(), static_cast<size_t>(rows / 10));
}

TEST(Visual, TessellatedShapesHaveTheirClosedFormSize) {
    mbd::VisualShape s;
    s.kind = mbd::ShapeKind::Box;
    s.size = Vec3(0.3, 0.5, 0.7);
    EXPECT_NEAR(enclosed_volume(mbd::viewer::shape_mesh(s)), 0.3 * 0.5 * 0.7, 1e-7);

    // a cylinder of N sides is a prism on the inscribed polygon: area N/2 r^2 sin(2 pi / N)
    s.kind = mbd::ShapeKind::Cylinder;
    s.radius = 0.2;
    s.length = 0.9;
    const auto cylinder = mbd::viewer::shape_mesh(s);
    const int n = 32;
    EXPECT_NEAR(enclosed_volume(cylinder), 0.5 * n * 0.04 * std::sin(2 * kPi / n) * 0.9, 1e-7);
    EXPECT_NEAR(cylinder.max[2] - cylinder.min[2], 0.9, 1e-7);
    // the coarser levels of scenes with many shapes: the same prism on fewer sides
    for (const size_t shapes : {100, 600, 5000}) {
        const mbd::viewer::Tessellation detail = mbd::viewer::tessellation_for(shapes);
        const int sides = detail.segments;
        EXPECT_NEAR(enclosed_volume(mbd::viewer::shape_mesh(s, detail)),
                    0.5 * sides * 0.04 * std::sin(2 * kPi / sides) * 0.9, 1e-7)
            << shapes << " shapes";
        EXPECT_GE(sides, 12) << "a cylinder of fewer sides no longer looks round";
    }

    s.kind = mbd::ShapeKind::Sphere;
    s.radius = 0.25;
    const auto sphere = mbd::viewer::shape_mesh(s);
    for (size_t k = 0; k < sphere.positions.size(); k += 3) {
        const Vec3 p(sphere.positions[k], sphere.positions[k + 1], sphere.positions[k + 2]);
        const Vec3 normal(sphere.normals[k], sphere.normals[k + 1], sphere.normals[k + 2]);
        ASSERT_NEAR(p.norm(), 0.25, 1e-7);
        ASSERT_NEAR(normal.norm(), 1.0, 1e-6);
        ASSERT_GT(normal.dot(p), 0.0);  // outward
    }
    EXPECT_GT(enclosed_volume(sphere), 0.9 * 4.0 / 3.0 * kPi * std::pow(0.25, 3));
    EXPECT_LT(enclosed_volume(sphere), 4.0 / 3.0 * kPi * std::pow(0.25, 3));

    // the tetrahedron of scenes/examples/meshes (vertices (+-0.08, +-0.08, +-0.08), an even
    // number of minus signs): volume (edge 0.16 sqrt 2)^3 / (6 sqrt 2) = 0.16^3 / 3
    s.kind = mbd::ShapeKind::Mesh;
    s.mesh_file = (mbd::test::source_dir() / "scenes/examples/meshes/tetrahedron.stl").string();
    const auto tetrahedron = mbd::viewer::shape_mesh(s);
    EXPECT_NEAR(enclosed_volume(tetrahedron), std::pow(0.16, 3) / 3.0, 1e-9);
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(tetrahedron.min[k], -0.08, 1e-7);
        EXPECT_NEAR(tetrahedron.max[k], 0.08, 1e-7);
    }
}

// ---------------------------------------------------------------- glTF read back

// Every body's translation and rotation samples equal the CSV row by row within 1e-6
// (the quaternion up to its sign: q and -q are one rotation).
void expect_samples_equal_csv(const std::string& scene, const std::string& args) {
    const fs::path dir = scratch("glb-" + fs::path(scene).stem().string());
    const auto r = run_mbd("simulate " + scene_file(scene) + " " + args + " -q --output " + quoted(dir / "r.csv") +
                           " --animation " + quoted(dir / "r.glb"));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const Csv csv = read_csv(dir / "r.csv");
    const Glb glb = load_glb(dir / "r.glb");
    const mbd::Model model = mbd::test::load(scene);
    const bool planar = model.dimension == mbd::Dimension::Planar;
    ASSERT_GE(csv.rows.size(), 10u);
    double worst = 0.0;
    for (const auto& body : model.bodies) {
        const int node = glb.node(body.name);
        ASSERT_GE(node, 0) << body.name;
        const auto [times, translation] = glb.channel(node, "translation");
        const auto [times_r, rotation] = glb.channel(node, "rotation");
        ASSERT_EQ(times.size(), csv.rows.size()) << body.name;
        ASSERT_EQ(rotation.size(), 4 * csv.rows.size()) << body.name;
        const int x = csv.column(body.name + ".x");
        for (size_t row = 0; row < csv.rows.size(); ++row) {
            const auto& v = csv.rows[row];
            worst = std::max(worst, std::abs(times[row] - v[0]));
            const double z = planar ? 0.0 : v[x + 2];
            for (int k = 0; k < 2; ++k) worst = std::max(worst, std::abs(translation[3 * row + k] - v[x + k]));
            worst = std::max(worst, std::abs(translation[3 * row + 2] - z));
            // glTF quaternions are (x, y, z, w); Euler parameters (e0, e1, e2, e3) = (w, x, y, z)
            double e[4];
            if (planar) {
                const double angle = v[csv.column(body.name + ".angle")];
                e[0] = std::cos(angle / 2), e[1] = 0, e[2] = 0, e[3] = std::sin(angle / 2);
            } else {
                for (int k = 0; k < 4; ++k) e[k] = v[x + 3 + k];
            }
            const double q[4] = {rotation[4 * row + 3], rotation[4 * row], rotation[4 * row + 1], rotation[4 * row + 2]};
            double same = 0.0, flipped = 0.0;
            for (int k = 0; k < 4; ++k) {
                same = std::max(same, std::abs(q[k] - e[k]));
                flipped = std::max(flipped, std::abs(q[k] + e[k]));
            }
            worst = std::max(worst, std::min(same, flipped));
        }
    }
    EXPECT_LE(worst, 1e-6) << scene;
    std::printf("%s: %zu rows x %d bodies, largest sample difference %.3g\n", scene.c_str(), csv.rows.size(),
                model.body_count(), worst);
}

TEST(Gltf, SamplesEqualTheCsvPosesFourBar) { expect_samples_equal_csv("four-bar.yaml", "--t-end 0.3 --output-step 0.005"); }
TEST(Gltf, SamplesEqualTheCsvPosesGyroscope) {
    expect_samples_equal_csv("bench/gyroscope.yaml", "--t-end 1 --output-step 0.01 --tol 1e-8");
}
TEST(Gltf, SamplesEqualTheCsvPosesChain50) { expect_samples_equal_csv("bench/chain-50.yaml", "--t-end 0.2 --output-step 0.01"); }
TEST(Gltf, SamplesEqualTheCsvPosesMeshScene) {
    expect_samples_equal_csv("examples/visual-shapes.yaml", "--t-end 1 --output-step 0.01");
}

// mbd statics --animation: one frame, each body node placed at the equilibrium the report gives.
TEST(Gltf, StaticsShowsTheEquilibrium) {
    const fs::path dir = scratch("glb-statics");
    const std::string scene = scene_file("statics/pendulum-torque.yaml");
    const auto r = run_mbd("statics " + scene + " --json --animation " + quoted(dir / "eq.glb"));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const Glb glb = load_glb(dir / "eq.glb");
    EXPECT_TRUE(glb.model.animations.empty());
    const mbd::Model model = mbd::test::load("statics/pendulum-torque.yaml");
    const nlohmann::json report = nlohmann::json::parse(r.out);
    for (const auto& body : model.bodies) {
        const nlohmann::json& at = report.at("bodies").at(body.name);
        const int node = glb.node(body.name);
        ASSERT_GE(node, 0);
        EXPECT_NEAR(glb.model.nodes[node].translation[0], at.at("x").get<double>(), 1e-12);
        EXPECT_NEAR(glb.model.nodes[node].translation[1], at.at("y").get<double>(), 1e-12);
    }
}

// ---------------------------------------------------------------- bad input

struct Failure {
    int exit_code;
    std::string err;
    bool left_output;
};

// mbd animate SCENE CSV -o out.EXT: exit code, message, and whether any output file remains.
Failure animate_fails(const fs::path& dir, const std::string& scene, const fs::path& csv, const std::string& ext) {
    const fs::path out = dir / ("out." + ext);
    const auto r = run_mbd("animate " + scene + " " + quoted(csv) + " -o " + quoted(out));
    return {r.exit_code, r.err, fs::exists(out) || fs::exists(out.string() + ".partial")};
}

fs::path four_bar_csv(const fs::path& dir) {
    const auto r = run_mbd("simulate " + scene_file("four-bar.yaml") + " --t-end 0.05 -q --output " +
                           quoted(dir / "four-bar.csv"));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return dir / "four-bar.csv";
}

TEST(BadInput, UnknownShapeAndMissingMeshNameFileLineAndKey) {
    const fs::path dir = scratch("bad-visual");
    const fs::path csv = four_bar_csv(dir);
    std::ifstream in(mbd::test::scene_path("four-bar.yaml"));
    std::string four_bar((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    // the crank's `name:` is on line 10 of four-bar.yaml; the visual goes on the line after it
    auto with_visual = [&](const std::string& visual) {
        std::string text = four_bar;
        const std::string anchor = "  - name: crank                      # O -> A\n";
        text.replace(text.find(anchor), anchor.size(), anchor + "    visual: " + visual + "\n");
        return text;
    };
    struct Case {
        std::string visual, expected;
    };
    const Case cases[] = {
        {"{shape: cylindre, radius: 0.01, length: 0.2}", "key 'shape': unknown shape 'cylindre'; did you mean 'cylinder'?"},
        {"{shape: mesh, file: no-such.stl}", "key 'file': mesh file"},
        {"{shape: sphere, radious: 0.1}", "unknown key 'radious' in a sphere visual; did you mean 'radius'?"},
    };
    for (const auto& c : cases) {
        write_text(dir / "bad.yaml", with_visual(c.visual));
        for (const char* ext : {"glb", "html"}) {
            const Failure f = animate_fails(dir, quoted(dir / "bad.yaml"), csv, ext);
            EXPECT_EQ(f.exit_code, 2) << c.visual;
            EXPECT_TRUE(contains(f.err, "bad.yaml:11: body 'crank': " + c.expected)) << f.err;
            EXPECT_FALSE(f.left_output) << c.visual;
        }
    }
}

TEST(BadInput, CsvOfAnotherSceneNamesTheColumn) {
    const fs::path dir = scratch("bad-csv");
    const fs::path csv = four_bar_csv(dir);
    const std::string gyroscope = scene_file("bench/gyroscope.yaml");
    Failure f = animate_fails(dir, gyroscope, csv, "html");  // four-bar columns for the gyroscope
    EXPECT_EQ(f.exit_code, 2);
    EXPECT_TRUE(contains(f.err, "four-bar.csv:1: column 2 'crank.x' names no body of the scene")) << f.err;
    EXPECT_FALSE(f.left_output);

    // the right scene but a column missing
    std::ifstream in(csv);
    std::string header, rest, line;
    std::getline(in, header);
    while (std::getline(in, line)) rest += line.substr(0, line.rfind(',')) + "\n";  // drop the last column
    write_text(dir / "short.csv", header.substr(0, header.rfind(',')) + "\n" + rest);
    f = animate_fails(dir, scene_file("four-bar.yaml"), dir / "short.csv", "glb");
    EXPECT_EQ(f.exit_code, 0) << "only a velocity column is missing: the poses are complete";
    // drop crank.angle (column 4) instead
    std::ifstream again(csv);
    std::string text;
    int row = 0;
    while (std::getline(again, line)) {
        std::vector<std::string> cells;
        std::stringstream s(line);
        std::string cell;
        while (std::getline(s, cell, ',')) cells.push_back(cell);
        cells.erase(cells.begin() + 3);
        for (size_t k = 0; k < cells.size(); ++k) text += (k ? "," : "") + cells[k];
        text += row++ == 3 ? ",x\n" : "\n";  // file line 4 gets one value too many
    }
    write_text(dir / "no-angle.csv", text);
    fs::remove(dir / "out.glb");
    f = animate_fails(dir, scene_file("four-bar.yaml"), dir / "no-angle.csv", "glb");
    EXPECT_EQ(f.exit_code, 2);
    EXPECT_TRUE(contains(f.err, "no-angle.csv:4: more values than the")) << f.err;  // read before matching
    EXPECT_FALSE(f.left_output);

    // a cell that is not a number
    std::string bad = header + "\n";
    std::ifstream third(csv);
    std::getline(third, line);
    std::getline(third, line);
    bad += line + "\n";
    std::getline(third, line);
    bad += line.substr(0, line.find(',') + 1) + "oops" + line.substr(line.find(',', line.find(',') + 1)) + "\n";
    write_text(dir / "nan.csv", bad);
    f = animate_fails(dir, scene_file("four-bar.yaml"), dir / "nan.csv", "html");
    EXPECT_EQ(f.exit_code, 2);
    EXPECT_TRUE(contains(f.err, "nan.csv:3: column 2 'crank.x': 'oops' is not a finite number")) << f.err;
    EXPECT_FALSE(f.left_output);
}

TEST(BadInput, MissingPoseColumnIsNamed) {
    const fs::path dir = scratch("bad-columns");
    write_text(dir / "r.csv", "t,crank.x,crank.y,coupler.x,coupler.y,coupler.angle,rocker.x,rocker.y,rocker.angle\n"
                         "0,0,0.1,0.14,0.34,0.79,0.34,0.24,4.95\n");
    const Failure f = animate_fails(dir, scene_file("four-bar.yaml"), dir / "r.csv", "glb");
    EXPECT_EQ(f.exit_code, 2);
    EXPECT_TRUE(contains(f.err, "r.csv:1: column 'crank.angle' is missing")) << f.err;
    EXPECT_FALSE(f.left_output);
}

TEST(BadInput, AnimationNameMustBeGlbOrHtml) {
    const fs::path dir = scratch("bad-extension");
    const auto r = run_mbd("simulate " + scene_file("four-bar.yaml") + " --t-end 0.01 -q --output " +
                           quoted(dir / "r.csv") + " --animation " + quoted(dir / "r.gltf"));
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_TRUE(contains(r.err, "r.gltf: an animation is written as .glb")) << r.err;
    EXPECT_FALSE(fs::exists(dir / "r.csv"));  // refused before the run
}

}  // namespace
