// Defaults that cannot be silently wrong (issue 42): the automatic choice takes the scales a
// scene holds into its tolerance and its stiffness class (tolerance_choice.hpp,
// method_choice.hpp), and a given tolerance too coarse for one of them is warned of.
//  - Book Ex. 5.6 (L6248-6352; digests/formulations.md 11.7, no misprint listed): the block on a
//    spring with Coulomb friction, v_s = 1e-9 m/s, stops at the 15th turning point,
//    x = -(0.03 - 15 * 2 F_f / k) = -5.70e-4 m, at t = 1.49 s; with no flags at all.
//  - A block sticking on a slope (tan(angle) = 0.3 < mu_s = 0.4) whose friction takes its load
//    from its guide's reaction: stiff while it sticks, at the regularized law's rate
//    1.5 mu_s N / (v_s m) with N = m g cos(angle) (coulomb_law.hpp), though its initial state
//    shows no friction at all.
#include "support/test_support.hpp"

#include <mbd/method_choice.hpp>
#include <mbd/tolerance_choice.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace {

namespace fs = std::filesystem;
using mbd::test::read_csv;
using mbd::test::run_mbd;
using mbd::test::scene_path;
using mbd::test::scratch;

bool contains(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

const std::string kExample5_6 = "extreme/friction-oscillator-ex5-6.yaml";
const std::string kStickingBlock = "automatic/friction-block-load-joint.yaml";

// The book's rest position: 15 half cycles, each losing 2 F_f / k = 2 (0.1 * 5 * 9.81) / 5000.
double example5_6_rest() { return -(0.03 - 15.0 * 2.0 * (0.1 * 5.0 * 9.81) / 5000.0); }

TEST(AutomaticTolerance, ResolvesTheStictionVelocityOfBookExample5_6) {
    EXPECT_NEAR(example5_6_rest(), -5.70e-4, 1e-12);  // the book's (digest 11.7) value
    const mbd::Model model = mbd::test::load(kExample5_6);
    const std::vector<mbd::VelocityScale> scales = mbd::velocity_scales(model);
    ASSERT_EQ(scales.size(), 1u);
    EXPECT_EQ(scales[0].element, "dry");
    EXPECT_EQ(scales[0].velocity, 1e-9);
    // tol (1 + v_s) = v_s / 10: the velocity error inside the band a tenth of its width
    const mbd::ToleranceChoice choice = mbd::automatic_tolerance(model, 1e-6);
    EXPECT_DOUBLE_EQ(choice.tolerance * (1.0 + 1e-9), 1e-9 / mbd::kVelocityResolution);
    EXPECT_TRUE(contains(choice.reason, "force 'dry'")) << choice.reason;
    // a scene without friction keeps the default
    const mbd::ToleranceChoice plain = mbd::automatic_tolerance(mbd::test::load("dynamics/pendulum-a01.yaml"), 1e-6);
    EXPECT_EQ(plain.tolerance, 1e-6);
}

// Every friction element holds a velocity scale: a pin's slip rate (rad/s), a compliant
// contact with friction, and an element without the key its documented default 1e-6.
TEST(AutomaticTolerance, FindsTheStictionVelocityOfEveryKindOfFrictionElement) {
    auto only_scale = [](const mbd::Model& model) {
        const std::vector<mbd::VelocityScale> scales = mbd::velocity_scales(model);
        EXPECT_EQ(scales.size(), 1u) << model.source;
        return scales.empty() ? mbd::VelocityScale{} : scales[0];
    };
    const mbd::VelocityScale pin = only_scale(mbd::test::load("examples/force-rotational-friction.yaml"));
    EXPECT_EQ(pin.element, "bearing");
    EXPECT_EQ(pin.velocity, 1e-6);
    const mbd::VelocityScale contact = only_scale(mbd::test::load("examples/force-circle-line.yaml"));
    EXPECT_EQ(contact.element, "slope");
    EXPECT_EQ(contact.velocity, 1e-4);
    EXPECT_DOUBLE_EQ(contact.tolerance, 1e-4 / (10.0 * (1.0 + 1e-4)));
    const std::string text = mbd::test::read_text(scene_path(kExample5_6));
    const mbd::VelocityScale fallback =
        only_scale(mbd::test::scene(mbd::test::replaced(text, "    stiction_velocity: 1.0e-9\n", "")));
    EXPECT_EQ(fallback.element, "dry");
    EXPECT_EQ(fallback.velocity, 1e-6);
    EXPECT_TRUE(mbd::velocity_scales(mbd::test::load("dynamics/pendulum-a01.yaml")).empty());
}

// The whole command, as a user runs it: no --tol, --integrator or --formulation.
TEST(AutomaticTolerance, BookExample5_6WithNoFlagsComesToRestWhereTheBookSays) {
    const fs::path out = scratch("ex5-6") / "ex5-6.csv";
    const auto run = run_mbd("simulate " + scene_path(kExample5_6).string() + " --t-end 2 -o " + out.string());
    ASSERT_EQ(run.exit_code, 0) << run.err;
    EXPECT_TRUE(contains(run.err, "integrator cvode (automatic: stiff")) << run.err;
    EXPECT_TRUE(contains(run.err, "tolerance 1e-10 (automatic: force 'dry' has stiction velocity 1e-09")) << run.err;
    const mbd::test::Csv csv = read_csv(out);
    const int x = csv.column("block.x");
    ASSERT_GE(x, 0);
    ASSERT_FALSE(csv.rows.empty());
    const double rest = csv.rows.back()[x];
    std::printf("Ex. 5.6 with no flags: rest at %.6e m (book %.6e m)\n", rest, example5_6_rest());
    EXPECT_NEAR(rest, example5_6_rest(), 1e-5);
    // at rest from t = 1.49 s on: every row after 1.6 s at the same place
    const int t = csv.column("t");
    for (const auto& row : csv.rows)
        if (row[t] > 1.6) EXPECT_NEAR(row[x], rest, 1e-8) << "t = " << row[t];
}

TEST(AutomaticTolerance, WarnsOfAGivenToleranceTooCoarseForAStictionVelocity) {
    const mbd::Model model = mbd::test::load(kExample5_6);
    const std::vector<std::string> warnings = mbd::tolerance_warnings(model, 1e-6);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_TRUE(contains(warnings[0], "force 'dry' has stiction velocity 1e-09")) << warnings[0];
    EXPECT_TRUE(contains(warnings[0], "at most 1e-10")) << warnings[0];
    EXPECT_TRUE(mbd::tolerance_warnings(model, 1e-10).empty());  // v_s / 10 as typed resolves it
    EXPECT_EQ(mbd::tolerance_warnings(model, 2e-10).size(), 1u);

    const fs::path dir = scratch("coarse");
    const std::string run = "simulate " + scene_path(kExample5_6).string() + " --t-end 0.05 -o " + (dir / "x.csv").string();
    const auto coarse = run_mbd(run + " --tol 1e-6");
    ASSERT_EQ(coarse.exit_code, 0) << coarse.err;
    EXPECT_TRUE(contains(coarse.err, "warning: force 'dry' has stiction velocity 1e-09, which the tolerance 1e-06 "
                                     "cannot resolve"))
        << coarse.err;
    EXPECT_TRUE(contains(coarse.err, "it needs a tolerance of at most 1e-10")) << coarse.err;
    const auto fine = run_mbd(run + " --tol 1e-10");
    ASSERT_EQ(fine.exit_code, 0) << fine.err;
    EXPECT_FALSE(contains(fine.err, "warning")) << fine.err;
}

TEST(AutomaticStiffness, FrictionLoadedThroughItsJointIsStiffWhileItSticks) {
    const mbd::Model model = mbd::test::load(kStickingBlock);
    const double angle = std::atan(0.3), m = 2.0, g = 9.81, mu_s = 0.4, v_s = 1e-6;
    // the law's slope at v = 0, 1.5 mu_s N / v_s, over the mass, N = m g cos(angle)
    const double rate = 1.5 * mu_s * m * g * std::cos(angle) / (v_s * m);  // 5.638e6 1/s
    EXPECT_EQ(mbd::fastest_damping_rate(model), 0.0);  // the initial state shows nothing: N = 0
    const mbd::StickingDamping sticking = mbd::sticking_damping_rate(model);
    std::printf("sticking block: damping rate %.6e 1/s (closed form %.6e)\n", sticking.rate, rate);
    EXPECT_NEAR(sticking.rate, rate, 1e-4 * rate);
    EXPECT_TRUE(contains(sticking.note, "force 'dry' loaded by joint 'slope''s static reaction 18.79 N")) << sticking.note;
    const mbd::MethodChoice choice = mbd::automatic_method(model, 1.0);
    ASSERT_EQ(choice.integrator, "cvode") << choice.integrator_reason;
    EXPECT_TRUE(contains(choice.integrator_reason, "stiff: fastest damping rate 5.64e+06 1/s (friction sticking"))
        << choice.integrator_reason;
    EXPECT_EQ(choice.formulation, "augmented") << choice.formulation_reason;  // the one that solves the load

    // the run with no flags finishes and the block sticks: it creeps at most v_s for 1 s
    const fs::path out = scratch("sticking") / "block.csv";
    const auto run = run_mbd("simulate " + scene_path(kStickingBlock).string() + " --t-end 1 -o " + out.string());
    ASSERT_EQ(run.exit_code, 0) << run.err;
    EXPECT_TRUE(contains(run.err, "integrator cvode (automatic: stiff")) << run.err;
    const mbd::test::Csv csv = read_csv(out);
    const int x = csv.column("block.x"), y = csv.column("block.y");
    ASSERT_EQ(csv.rows.size(), 1001u);
    const double travel = std::hypot(csv.rows.back()[x] - csv.rows.front()[x], csv.rows.back()[y] - csv.rows.front()[y]);
    std::printf("sticking block: travel over 1 s %.3e m\n", travel);
    EXPECT_LT(travel, v_s * 1.0);
    // it creeps where the law's band balances the slope's pull: mu(v) N = m g sin(angle), with
    // mu = mu_s (3 x - x^3) / 2, x = v / v_s, N = m g cos(angle): 3 x - x^3 = 2 tan(angle) / mu_s
    double creep = 0.5;  // Newton on the cubic
    for (int k = 0; k < 50; ++k)
        creep -= (3.0 * creep - creep * creep * creep - 2.0 * 0.3 / mu_s) / (3.0 - 3.0 * creep * creep);
    const int vx = csv.column("block.vx"), vy = csv.column("block.vy");
    const double speed = std::hypot(csv.rows.back()[vx], csv.rows.back()[vy]);
    std::printf("sticking block: creep %.6e m/s (closed form %.6e)\n", speed, creep * v_s);
    EXPECT_NEAR(speed, creep * v_s, 1e-4 * creep * v_s);
}

}  // namespace
