// Per-contact output (issue 39 item 4; mbd/contact_output.hpp): `mbd simulate --contacts FILE`
// writes every active contact of the collision shapes, one row per contact and output time.
// Against independent oracles:
//  - a box at rest on a plane reports its 4 corners: each point is the corner (placed by the
//    box's pose in the motion output and its size) carried to the plane along the normal by the
//    reported depth, the depths are the corners' heights below the plane, and the normal
//    forces sum to m g (1e-8), a quarter on each corner, with no friction;
//  - a sphere at rest on a plane reports the depth the Hunt-Crossley law holds its weight at,
//    k d^n = m g, at the foot of its centre;
//  - a scene without collision shapes is refused, naming the option.
#include "support/test_support.hpp"

#include <mbd/sdk/rotation.hpp>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace {

using mbd::test::g17;
using mbd::test::read_csv;
using mbd::test::run_mbd;

constexpr double kG = 9.81;

struct Outputs {
    mbd::test::Csv motion, contacts;
};

// Simulates `yaml` with cvode at a tight tolerance to t_end, an output row each second.
Outputs simulate(const std::string& name, const std::string& yaml, double t_end) {
    const auto dir = mbd::test::scratch(name);
    const auto scene = mbd::test::write_text(dir / "scene.yaml", yaml);
    const auto r = run_mbd("simulate " + scene.string() + " --t-end " + g17(t_end) +
                           " --output-step 1 --integrator cvode --tol 1e-10 -q --output " +
                           (dir / "motion.csv").string() + " --contacts " + (dir / "contacts.csv").string());
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return {read_csv(dir / "motion.csv"), read_csv(dir / "contacts.csv")};
}

// The contact rows at time t.
std::vector<std::vector<double>> rows_at(const mbd::test::Csv& csv, double t) {
    std::vector<std::vector<double>> out;
    for (const auto& row : csv.rows)
        if (row[0] == t) out.push_back(row);
    return out;
}

Eigen::Vector3d column3(const std::vector<double>& row, int first) { return {row[first], row[first + 1], row[first + 2]}; }

// The body's pose in the last row of the motion output.
struct Pose {
    Eigen::Vector3d position;
    Eigen::Matrix3d rotation;
};
Pose last_pose(const mbd::test::Csv& motion, const std::string& body) {
    const auto& row = motion.rows.back();
    const auto at = [&](const char* s) { return row[motion.column(body + s)]; };
    const mbd::Vec4 p(at(".e0"), at(".e1"), at(".e2"), at(".e3"));
    return {{at(".x"), at(".y"), at(".z")}, mbd::rotation_from_euler_parameters(p / p.norm())};
}

TEST(ContactOutput, BoxAtRestReportsItsFourCornersCarryingItsWeight) {
    const double m = 2.0, k = 1e8, n = 1.5;
    const Eigen::Vector3d half(0.2, 0.1, 0.05);
    const Outputs run = simulate("box", "dimension: spatial\ngravity: [0, 0, -9.81]\n"
        "ground:\n  collision:\n    - {shape: plane, normal: [0, 0, 1], material: {static_friction: 1}}\n"
        "bodies:\n  - name: box\n    mass: 2\n    inertia: [0.008333333333333333, 0.02833333333333333, "
        "0.03333333333333333]\n    position: [0.3, -0.2, 0.0502]\n    orientation: {axis: [1, 2, 0], angle: 0.002}\n"
        "    collision:\n      - shape: box\n        size: [0.4, 0.2, 0.1]\n"
        "        material: {stiffness: 1e8, exponent: 1.5, damping: 6e9, static_friction: 0.5, "
        "stiction_velocity: 1e-4}\n", 3.0);
    ASSERT_EQ(run.contacts.header.size(), 17u);  // ... friction_x..z, rolling_x..z
    const auto rows = rows_at(run.contacts, 3.0);
    ASSERT_EQ(rows.size(), 4u);
    const Pose box = last_pose(run.motion, "box");
    std::vector<int> corners_found;
    double weight = 0.0;
    for (const auto& c : rows) {
        // the box's force: on body j along n, or its opposite when the box is body i
        ASSERT_TRUE((c[1] == -1 && c[2] == 0) || (c[1] == 0 && c[2] == -1)) << c[1] << " " << c[2];
        const double on_box = c[2] == 0 ? 1.0 : -1.0;
        const Eigen::Vector3d normal = column3(c, 6);
        const Eigen::Vector3d up = on_box * normal;
        EXPECT_NEAR((up - Eigen::Vector3d::UnitZ()).norm(), 0.0, 1e-15);
        const double depth = c[9];
        const Eigen::Vector3d force = on_box * (c[10] * normal + column3(c, 11));
        weight += force.z();
        EXPECT_NEAR(force.z(), m * kG / 4, 1e-6 * m * kG) << "the level box's corners share its weight equally";
        EXPECT_NEAR(std::pow(depth, n) * k, force.z(), 1e-9 * m * kG) << "the normal law at the reported depth";
        EXPECT_LT(column3(c, 11).norm(), 1e-8 * m * kG) << "at rest: no friction";
        EXPECT_EQ(column3(c, 14).norm(), 0.0) << "no rolling resistance between flat faces";
        // which corner: the one the point lies over
        int found = -1;
        for (int corner = 0; corner < 8; ++corner) {
            const Eigen::Vector3d local((corner & 1 ? 1 : -1) * half.x(), (corner & 2 ? 1 : -1) * half.y(),
                                        (corner & 4 ? 1 : -1) * half.z());
            const Eigen::Vector3d X = box.position + box.rotation * local;
            if ((X + depth * Eigen::Vector3d::UnitZ() - column3(c, 3)).norm() < 1e-12) {
                found = corner;
                EXPECT_NEAR(depth, -X.z(), 1e-12) << "the depth is the corner's depth below the plane";
            }
        }
        EXPECT_GE(found, 0) << "the point " << column3(c, 3).transpose() << " is no corner of the box";
        EXPECT_LT(found, 4) << "a bottom corner";
        corners_found.push_back(found);
    }
    std::sort(corners_found.begin(), corners_found.end());
    EXPECT_EQ(corners_found, (std::vector<int>{0, 1, 2, 3}));
    EXPECT_NEAR(weight, m * kG, 1e-8 * m * kG);
    RecordProperty("weight_error", g17(weight - m * kG));
}

TEST(ContactOutput, SphereAtRestReportsTheHuntCrossleyDepthOfItsWeight) {
    const double m = 1.5, k = 2e6, n = 1.5, radius = 0.1;
    const Outputs run = simulate("sphere", "dimension: spatial\ngravity: [0, 0, -9.81]\n"
        "ground:\n  collision:\n    - {shape: plane, normal: [0, 0, 1]}\n"
        "bodies:\n  - name: ball\n    mass: 1.5\n    inertia: [0.006, 0.006, 0.006]\n    position: [0.2, 0.1, 0.11]\n"
        "    collision:\n      - shape: sphere\n        radius: 0.1\n"
        "        material: {stiffness: 2e6, exponent: 1.5, restitution: 0.2, impact_velocity: 0.1}\n", 4.0);
    EXPECT_TRUE(rows_at(run.contacts, 0.0).empty()) << "dropped from above the plane: no contact at t = 0";
    const auto rows = rows_at(run.contacts, 4.0);
    ASSERT_EQ(rows.size(), 1u);
    const auto& c = rows[0];
    const double depth = std::pow(m * kG / k, 1.0 / n);  // k d^n = m g
    EXPECT_NEAR(c[9], depth, 1e-9 * depth);
    EXPECT_NEAR(std::abs(c[10]), m * kG, 1e-9 * m * kG);
    const Pose ball = last_pose(run.motion, "ball");
    EXPECT_NEAR(ball.position.z(), radius - depth, 1e-12) << "the motion agrees with the reported depth";
    EXPECT_NEAR(c[3], ball.position.x(), 1e-12) << "the contact is at the foot of the centre";
    EXPECT_NEAR(c[4], ball.position.y(), 1e-12);
    EXPECT_NEAR(std::abs(c[8]), 1.0, 1e-15);
    RecordProperty("depth_error", g17(c[9] - depth));
}

TEST(ContactOutput, ASceneWithoutCollisionShapesIsRefusedNamingTheOption) {
    const auto dir = mbd::test::scratch("none");
    const auto r = run_mbd("simulate " + mbd::test::scene_path("four-bar.yaml").string() + " --t-end 0.1 -q -o " +
                           (dir / "x.csv").string() + " --contacts " + (dir / "c.csv").string());
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("--contacts"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("collision:"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "x.csv"));
    EXPECT_FALSE(std::filesystem::exists(dir / "c.csv"));
}

}  // namespace
