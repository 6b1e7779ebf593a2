// Compliant contacts in the automatic choice (issue 42, Build 1; contact_scales.hpp): the
// penetration a contact holds and its frequency from the normal law's closed forms, the tolerance
// that resolves the penetration, the stiffness class from the frequency, and a ball that comes to
// rest at the height the law gives when run with no flags.
//  - at rest under the weight m g: k delta_s^n = m g, delta_s = (m g / k)^(1/n);
//  - at an impact at v_i: k delta_i^(n+1) / (n + 1) = m v_i^2 / 2;
//  - frequency sqrt(n k delta^(n-1) / m), the law's slope over the mass, m the reduced mass of
//    two free bodies.
#include "support/test_support.hpp"

#include <mbd/contact_scales.hpp>
#include <mbd/method_choice.hpp>
#include <mbd/tolerance_choice.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace {

namespace fs = std::filesystem;

bool contains(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

// A steel ball (1 kg, radius 0.05 m) touching the ground plane at rest, Hertz contact of
// stiffness k, damping fitted to a restitution of 0.1 at 0.01 m/s.
std::string ball_scene(double stiffness, const std::string& gravity = "[0, 0, -9.81]") {
    return "name: resting-ball\ndimension: spatial\ngravity: " + gravity +
           "\nbodies:\n"
           "  - {name: ball, mass: 1.0, inertia: [1.0e-3, 1.0e-3, 1.0e-3], position: [0, 0, 0.05]}\n"
           "forces:\n"
           "  - {name: floor, type: sphere_plane, bodies: [ground, ball], normal: [0, 0, 1], radius: 0.05,\n"
           "     stiffness: " + std::to_string(stiffness) +
           ", exponent: 1.5, restitution: 0.1, impact_velocity: 0.01}\n";
}

const double g = 9.81;

TEST(ContactScales, PenetrationAndFrequencyOfABallOnTheGroundFromTheLaw) {
    const double k = 1e9, n = 1.5, m = 1.0, v = 0.01;
    const std::vector<mbd::ContactScale> scales = mbd::contact_scales(mbd::test::scene(ball_scene(k)));
    ASSERT_EQ(scales.size(), 1u);
    const mbd::ContactScale& s = scales[0];
    const double at_rest = std::pow(m * g / k, 1.0 / n);                            // 4.58e-6 m
    const double at_impact = std::pow((n + 1.0) * m * v * v / (2.0 * k), 1.0 / (n + 1.0));  // 6.9e-6 m
    ASSERT_LT(at_rest, at_impact);
    EXPECT_EQ(s.element, "floor");
    EXPECT_NEAR(s.mass, m, 1e-15);
    EXPECT_NEAR(s.penetration, at_rest, 1e-12 * at_rest);
    EXPECT_TRUE(contains(s.penetration_source, "at rest under its weight 9.81 N")) << s.penetration_source;
    // the faster oscillation is at the deeper penetration (n > 1)
    EXPECT_NEAR(s.frequency, std::sqrt(n * k * std::pow(at_impact, n - 1.0) / m), 1e-9 * s.frequency);
    EXPECT_NEAR(s.extent, 0.05, 1e-15);
    EXPECT_NEAR(s.tolerance, at_rest / (10.0 * 1.05), 1e-12 * s.tolerance);
}

TEST(ContactScales, TwoFreeBodiesUseTheirReducedMassAndAnImpactWithoutGravity) {
    // scenes/examples/force-sphere-sphere.yaml: two 0.17 kg balls, k = 5e9, n = 1.5, v_i = 2 m/s,
    // no gravity: the only scale is the impact's
    const std::vector<mbd::ContactScale> scales = mbd::contact_scales(mbd::test::load("examples/force-sphere-sphere.yaml"));
    ASSERT_EQ(scales.size(), 1u);
    const double k = 5e9, n = 1.5, m = 0.17 * 0.17 / 0.34, v = 2.0;
    const double at_impact = std::pow((n + 1.0) * m * v * v / (2.0 * k), 1.0 / (n + 1.0));
    EXPECT_NEAR(scales[0].mass, m, 1e-15);
    EXPECT_NEAR(scales[0].penetration, at_impact, 1e-12 * at_impact);
    EXPECT_TRUE(contains(scales[0].penetration_source, "at its impact at 2 m/s")) << scales[0].penetration_source;
    EXPECT_NEAR(scales[0].frequency, std::sqrt(n * k * std::pow(at_impact, n - 1.0) / m), 1e-9 * scales[0].frequency);
    EXPECT_NEAR(scales[0].extent, 0.1, 1e-15);

    // neither gravity nor an impact velocity: nothing is known before the run
    std::string free_ball = ball_scene(1e9, "[0, 0, 0]");
    free_ball.replace(free_ball.find(", restitution: 0.1, impact_velocity: 0.01"),
                      std::string(", restitution: 0.1, impact_velocity: 0.01").size(), ", damping: 10");
    EXPECT_TRUE(mbd::contact_scales(mbd::test::scene(free_ball)).empty());
    // elements without a compliant law hold none
    EXPECT_TRUE(mbd::contact_scales(mbd::test::load("dynamics/pendulum-a01.yaml")).empty());
}

// Collision shapes (collision_contact): each body's stiffest law against the ground's shapes, or
// against its own kind when the ground has none: two equal materials in series,
// k^(-1/n) = 2 k_1^(-1/n), k = k_1 / 2^n, carrying the reduced mass m / 2.
TEST(ContactScales, CollisionShapesGiveEachBodyItsStiffestLaw) {
    const std::string sphere = "collision: [{shape: sphere, radius: 0.1, material: {stiffness: 1.0e8, exponent: 1.5}}]";
    const std::string bodies = "  - {name: a, mass: 2.0, inertia: [0.01, 0.01, 0.01], position: [0, 0, 0.3], " + sphere +
                               "}\n  - {name: b, mass: 0.5, inertia: [0.01, 0.01, 0.01], position: [1, 0, 0.2], " +
                               sphere + "}\n";
    const std::string head = "name: shapes\ndimension: spatial\ngravity: [0, 0, -9.81]\n";
    const double n = 1.5;
    {   // on a rigid ground plane: each body carries its own weight, k as given
        const mbd::Model model = mbd::test::scene(head + "ground:\n  collision: [{shape: plane, normal: [0, 0, 1]}]\n"
                                                  "bodies:\n" + bodies);
        const std::vector<mbd::ContactScale> scales = mbd::contact_scales(model);
        ASSERT_EQ(scales.size(), 2u);
        for (const auto& body : {std::pair{2.0, 0.3}, std::pair{0.5, 1.0}}) {
            const double m = body.first, extent = body.second;
            const auto s = std::find_if(scales.begin(), scales.end(), [&](const auto& x) { return x.mass == m; });
            ASSERT_NE(s, scales.end()) << m;
            const double delta = std::pow(m * g / 1e8, 1.0 / n);
            EXPECT_NEAR(s->penetration, delta, 1e-12 * delta);
            EXPECT_NEAR(s->frequency, std::sqrt(n * 1e8 * std::pow(delta, n - 1.0) / m), 1e-9 * s->frequency);
            EXPECT_NEAR(s->extent, extent, 1e-15);
        }
    }
    {   // no ground shapes: each against its own kind, half its mass on the series law
        const std::vector<mbd::ContactScale> scales = mbd::contact_scales(mbd::test::scene(head + "bodies:\n" + bodies));
        ASSERT_EQ(scales.size(), 2u);
        const double k = 1e8 / std::pow(2.0, n);
        for (const double m : {2.0, 0.5}) {
            const auto s = std::find_if(scales.begin(), scales.end(), [&](const auto& x) { return x.mass == m / 2; });
            ASSERT_NE(s, scales.end()) << m;
            const double delta = std::pow(m / 2 * g / k, 1.0 / n);
            EXPECT_NEAR(s->penetration, delta, 1e-12 * delta);
            EXPECT_NEAR(s->frequency, std::sqrt(n * k * std::pow(delta, n - 1.0) / (m / 2)), 1e-9 * s->frequency);
        }
    }
}

TEST(AutomaticTolerance, ResolvesTheRestingPenetrationOfAStiffContact) {
    const mbd::Model model = mbd::test::scene(ball_scene(1e9));
    const double at_rest = std::pow(g / 1e9, 1.0 / 1.5), needed = at_rest / (10.0 * 1.05);  // 4.4e-7
    const mbd::ToleranceChoice choice = mbd::automatic_tolerance(model, 1e-6);
    EXPECT_NEAR(choice.tolerance, needed, 1e-12 * needed);
    EXPECT_TRUE(contains(choice.reason, "force 'floor' has a penetration of 4.58e-06 m at rest under its weight"))
        << choice.reason;
    const std::vector<std::string> warnings = mbd::tolerance_warnings(model, 1e-6);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_TRUE(contains(warnings[0], "force 'floor' has a penetration of 4.58e-06 m")) << warnings[0];
    EXPECT_TRUE(contains(warnings[0], "at most 4.36e-07")) << warnings[0];
    EXPECT_TRUE(mbd::tolerance_warnings(model, needed).empty());
    // a soft contact's penetration is resolved by the default
    const mbd::ToleranceChoice soft = mbd::automatic_tolerance(mbd::test::scene(ball_scene(1e5)), 1e-6);
    EXPECT_EQ(soft.tolerance, 1e-6) << soft.reason;
}

TEST(AutomaticStiffness, AStiffContactIsStiffOverALongRun) {
    const double k = 1e9, n = 1.5, m = 1.0, v = 0.01;
    const double at_impact = std::pow((n + 1.0) * m * v * v / (2.0 * k), 1.0 / (n + 1.0));
    const double w = std::sqrt(n * k * std::pow(at_impact, n - 1.0) / m);  // 1.98e3 rad/s
    const mbd::Model model = mbd::test::scene(ball_scene(k));
    EXPECT_NEAR(mbd::fastest_contact_frequency(model).frequency, w, 1e-9 * w);
    // w t_end against kStiffDampedTimeScales = 1e4
    const double short_run = 0.5 * mbd::kStiffDampedTimeScales / w, long_run = 2.0 * mbd::kStiffDampedTimeScales / w;
    const mbd::MethodChoice quick = mbd::automatic_method(model, short_run);
    EXPECT_EQ(quick.integrator, "dop853") << quick.integrator_reason;
    const mbd::MethodChoice slow = mbd::automatic_method(model, long_run);
    EXPECT_EQ(slow.integrator, "cvode") << slow.integrator_reason;
    EXPECT_TRUE(contains(slow.integrator_reason, "stiff: fastest contact frequency 1.98e+03")) << slow.integrator_reason;
    EXPECT_TRUE(contains(slow.integrator_reason, "compliant contact 'floor'")) << slow.integrator_reason;
}

TEST(AutomaticTolerance, ABallRestsWhereItsContactLawHoldsItWithNoFlags) {
    const fs::path dir = mbd::test::scratch("resting-ball");
    const fs::path scene = dir / "ball.yaml", out = dir / "ball.csv";
    mbd::test::write_text(scene, ball_scene(1e9));
    const auto run = mbd::test::run_mbd("simulate " + scene.string() + " --t-end 0.2 -o " + out.string());
    ASSERT_EQ(run.exit_code, 0) << run.err;
    EXPECT_TRUE(contains(run.err, "tolerance 4.36e-07 (automatic: force 'floor' has a penetration")) << run.err;
    const mbd::test::Csv csv = mbd::test::read_csv(out);
    const int z = csv.column("ball.z");
    const double at_rest = std::pow(g / 1e9, 1.0 / 1.5);
    // settled by 0.1 s (damping ratio 0.2 at 1.8e3 rad/s): within a tenth of the penetration
    for (const auto& row : csv.rows)
        if (row[csv.column("t")] > 0.1) EXPECT_NEAR(row[z], 0.05 - at_rest, 0.1 * at_rest) << "t = " << row[0];
}

}  // namespace
