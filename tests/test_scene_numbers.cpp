// Every number in a scene goes through one reader (mbd/sdk/number.hpp): finite, in the
// range of a double, whole where a count is meant, and refused at file:line naming the
// key and the element. Inertias must be physically possible: principal moments >= 0 and
// each at most the sum of the other two (Shabana Eq. 7.95), flat bodies on the boundary.
#include <mbd/scene.hpp>
#include <mbd/sdk/number.hpp>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "support/test_support.hpp"

namespace {

namespace fs = std::filesystem;

#define EXPECT_CONTAINS(text, part) \
    EXPECT_NE(std::string(text).find(part), std::string::npos) << "'" << (text) << "' lacks '" << (part) << "'"

std::string load_error(const std::string& yaml) {
    try {
        mbd::load_scene_text(yaml, "test.yaml", mbd::test::shared_registry());
    } catch (const mbd::InputError& e) {
        return e.what();
    }
    ADD_FAILURE() << "expected an InputError, the scene loaded:\n" << yaml;
    return {};
}

std::string replace(std::string text, const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << "test bug: '" << from << "' not in the scene";
    if (at != std::string::npos) text.replace(at, from.size(), to);
    return text;
}

// A planar scene exercising the core (bodies, gravity, joints), a joint plugin key
// (gear_pair radii), a force plugin (spring_damper) and a time function (driver).
// Line numbers matter: the tests below edit single lines.
const std::string kPlanar = R"(dimension: planar
gravity: [0, -9.81]
bodies:
  - {name: gear1, mass: 1, inertia: 0.01, position: [0, 0]}
  - {name: gear2, mass: 1, inertia: 0.01, position: [0.15, 0]}
joints:
  - {name: pin1, type: revolute, bodies: [ground, gear1], point: [0, 0]}
  - {name: pin2, type: revolute, bodies: [ground, gear2], point: [0.15, 0]}
  - {name: mesh, type: gear_pair, bodies: [gear1, gear2], radii: [0.1, 0.05]}
forces:
  - {name: spring, type: spring_damper, bodies: [ground, gear2], points: [[0.3, 0], [0, 0.05]], stiffness: 250}
drivers:
  - {name: motor, joint: pin1, motion: {type: linear, initial: 0, rate: 1}}
)";

// A spatial scene for the inertia rules (one free body).
std::string spatial_body(const std::string& inertia) {
    return "dimension: spatial\nbodies:\n  - name: plate\n    mass: 2\n    inertia: " + inertia + "\n";
}

}  // namespace

TEST(SceneNumbers, TheReaderRefusesEverySpellingOfNanAndInfinity) {
    for (const char* text : {"nan", "NaN", ".nan", "inf", "-inf", ".inf", "-.Inf", "+.INF", "infinity", "nan(1)"}) {
        double value = 42.0;
        EXPECT_EQ(mbd::parse_number(text, value), mbd::NumberText::NotFinite) << text;
        EXPECT_EQ(value, 42.0) << text;
    }
    for (const char* text : {"1e999", "-1e400", "1e-400"}) {
        double value = 0.0;
        EXPECT_EQ(mbd::parse_number(text, value), mbd::NumberText::OutOfRange) << text;
    }
    for (const char* text : {"", "abc", "1x", "0x10", "+-1", "--1", "1e", " 1", "1,5", "+"}) {
        double value = 0.0;
        EXPECT_EQ(mbd::parse_number(text, value), mbd::NumberText::NotANumber) << "'" << text << "'";
    }
    const std::pair<const char*, double> valid[] = {{"0", 0.0},      {"+2.5", 2.5},   {"-1.5e3", -1500.0},
                                                    {".25", 0.25},   {"1.", 1.0},     {"6.02214076e23", 6.02214076e23},
                                                    {"1e-310", 1e-310}, {"-0", 0.0}};
    for (const auto& [text, expected] : valid) {
        double value = -7.0;
        EXPECT_EQ(mbd::parse_number(text, value), mbd::NumberText::Valid) << text;
        EXPECT_EQ(value, expected) << text;
    }
}

// One refusal per kind of reader that used to exist: core keys, core vectors, a joint
// plugin's key, a force plugin's key, a time function's key and a constant time function.
TEST(SceneNumbers, NonFiniteValuesAreRefusedAtTheirLineNamingTheKey) {
    struct Case {
        std::string from, to;
        int line;
        std::string key, element;
    };
    const Case cases[] = {
        {"mass: 1, inertia: 0.01, position: [0, 0]", "mass: .nan, inertia: 0.01, position: [0, 0]", 4, "'mass'",
         "body 'gear1'"},
        {"inertia: 0.01, position: [0.15, 0]", "inertia: inf, position: [0.15, 0]", 5, "'inertia'", "body 'gear2'"},
        {"position: [0.15, 0]}", "position: [0.15, -.inf]}", 5, "'position'", "body 'gear2'"},
        {"gravity: [0, -9.81]", "gravity: [0, -Infinity]", 2, "'gravity'", "scene"},
        {"radii: [0.1, 0.05]", "radii: [0.1, nan]", 9, "'radii'", "gear_pair 'mesh'"},
        {"stiffness: 250", "stiffness: -.inf", 11, "'stiffness'", "force 'spring'"},
        {"rate: 1", "rate: .NaN", 13, "'rate'", "driver 'motor'"},
        {"motion: {type: linear, initial: 0, rate: 1}", "motion: inf", 13, "'value'", "driver 'motor'"},
    };
    for (const Case& c : cases) {
        const std::string msg = load_error(replace(kPlanar, c.from, c.to));
        EXPECT_CONTAINS(msg, "test.yaml:" + std::to_string(c.line));
        EXPECT_CONTAINS(msg, c.key + " must be a finite number");
        EXPECT_CONTAINS(msg, c.element);
    }
    const std::string huge = load_error(replace(kPlanar, "stiffness: 250", "stiffness: 1e999"));
    EXPECT_CONTAINS(huge, "test.yaml:11");
    EXPECT_CONTAINS(huge, "'stiffness' is out of the range of a double");
}

// A count in a formulation (read when the analysis creates it): a whole number in range,
// never infinity cast to int. Checked through `mbd simulate`, which must stop before running.
TEST(SceneNumbers, CountsAreWholeNumbersInRange) {
    const fs::path dir = mbd::test::scratch("counts");
    struct Case {
        std::string formulation, part;
    };
    const Case cases[] = {
        {"{type: augmented, sparse_threshold: inf}", "'sparse_threshold' must be a finite number, got 'inf'"},
        {"{type: augmented, sparse_threshold: 1e20}", "'sparse_threshold' must be between 1 and 1000000000"},
        {"{type: augmented, sparse_threshold: 2.5}", "'sparse_threshold' must be a whole number"},
        {"{type: embedding, newton_iterations: .nan}", "'newton_iterations' must be a finite number"},
        {"{type: hamiltonian, newton_iterations: 0}", "'newton_iterations' must be between 1 and 1000000"},
    };
    int index = 0;
    for (const Case& c : cases) {
        const fs::path scene = dir / ("scene" + std::to_string(index) + ".yaml");
        const fs::path output = dir / ("out" + std::to_string(index++) + ".csv");
        std::ofstream(scene) << "dimension: planar\nformulation: " << c.formulation
                             << "\nbodies:\n  - {name: link, mass: 1, inertia: 0.1, position: [0.5, 0]}\n"
                                "joints:\n  - {name: pin, type: revolute, bodies: [ground, link], point: [0, 0]}\n";
        const auto r = mbd::test::run_mbd("simulate '" + scene.string() + "' --t-end 0.01 -q -o '" +
                                          output.string() + "'");
        EXPECT_EQ(r.exit_code, 2) << r.err;
        EXPECT_CONTAINS(r.err, scene.string() + ":2");
        EXPECT_CONTAINS(r.err, c.part);
        EXPECT_FALSE(fs::exists(output)) << c.formulation;
    }
}

TEST(SceneNumbers, PrincipalMomentsViolatingTheTriangleInequalityAreRefused) {
    const std::string msg = load_error(spatial_body("[1, 1, 3]"));
    EXPECT_CONTAINS(msg, "test.yaml:5");
    EXPECT_CONTAINS(msg, "body 'plate'");
    EXPECT_CONTAINS(msg, "3 exceeds the sum of the other two (1 + 1)");
    // any order of the moments
    EXPECT_CONTAINS(load_error(spatial_body("[0.5, 2, 1]")), "2 exceeds the sum of the other two (1 + 0.5)");

    // the same impossible body given as a full tensor in rotated axes: its eigenvalues are checked
    const Eigen::Matrix3d A = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    const Eigen::Matrix3d J = A * Eigen::Vector3d(1, 1, 3).asDiagonal() * A.transpose();
    std::string tensor = "[";
    for (int r = 0; r < 3; ++r) {
        tensor += r ? ", [" : "[";
        for (int c = 0; c < 3; ++c) tensor += (c ? ", " : "") + mbd::test::g17(0.5 * (J(r, c) + J(c, r)));
        tensor += "]";
    }
    tensor += "]";
    const std::string full = load_error(spatial_body(tensor));
    EXPECT_CONTAINS(full, "test.yaml:5");
    EXPECT_CONTAINS(full, "body 'plate'");
    EXPECT_CONTAINS(full, "principal moments (eigenvalues)");
    EXPECT_CONTAINS(full, "exceeds the sum of the other two");
}

TEST(SceneNumbers, FlatBodiesOnTheTriangleBoundaryAreValid) {
    // thin disk of mass m, radius r: J_x = J_y = m r^2 / 4, J_z = m r^2 / 2 = J_x + J_y
    const double m = 2.0, r = 0.3;
    const double Jd = m * r * r / 4;
    const std::string disk = "[" + mbd::test::g17(Jd) + ", " + mbd::test::g17(Jd) + ", " +
                             mbd::test::g17(m * r * r / 2) + "]";
    const mbd::Model model = mbd::test::scene(spatial_body(disk));
    EXPECT_DOUBLE_EQ(model.bodies[0].inertia(2, 2), m * r * r / 2);
    // the exact boundary, a thin rod (one moment zero) and a massless body all load
    EXPECT_EQ(mbd::test::scene(spatial_body("[1, 1, 2]")).body_count(), 1);
    EXPECT_EQ(mbd::test::scene(spatial_body("[0.5, 0.5, 0]")).body_count(), 1);
    EXPECT_EQ(mbd::test::scene("dimension: spatial\nbodies:\n  - {name: l, mass: 0, inertia: [0, 0, 0]}\n").body_count(),
              1);
    // a rotated thin disk given as a full tensor: its eigenvalues sit on the boundary up to rounding
    const Eigen::Matrix3d A = Eigen::AngleAxisd(1.1, Eigen::Vector3d(3, -1, 2).normalized()).toRotationMatrix();
    const Eigen::Matrix3d J = A * Eigen::Vector3d(Jd, Jd, 2 * Jd).asDiagonal() * A.transpose();
    std::string tensor = "[";
    for (int row = 0; row < 3; ++row) {
        tensor += row ? ", [" : "[";
        for (int c = 0; c < 3; ++c) tensor += (c ? ", " : "") + mbd::test::g17(0.5 * (J(row, c) + J(c, row)));
        tensor += "]";
    }
    tensor += "]";
    const mbd::Model rotated = mbd::test::scene(spatial_body(tensor));
    EXPECT_NEAR(rotated.bodies[0].inertia.trace(), 4 * Jd, 1e-15);
    // a negative moment in a full tensor is refused with the moments listed
    EXPECT_CONTAINS(load_error(spatial_body("[[1, 0, 0], [0, 1, 2], [0, 2, 1]]")), "not positive semi-definite");
}

TEST(SceneNumbers, PlanarInertiaMustBeFiniteAndNotNegative) {
    EXPECT_CONTAINS(load_error(replace(kPlanar, "inertia: 0.01, position: [0, 0]", "inertia: -0.01, position: [0, 0]")),
                    "'inertia' must be positive (or 0)");
    // a massless planar link (mass 0, inertia 0) stays valid for kinematics
    const mbd::Model massless =
        mbd::test::scene(replace(kPlanar, "mass: 1, inertia: 0.01, position: [0, 0]", "mass: 0, inertia: 0, position: [0, 0]"));
    EXPECT_EQ(massless.bodies[0].mass, 0.0);
}
