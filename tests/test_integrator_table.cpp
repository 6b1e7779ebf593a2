// The integrators' table (mbd/integrator.hpp integrator_descriptions(), one row each in
// core/src/integrators/table.cpp) checked against what each integrator does, not against
// itself: the order a fixed-step method is described with is the order measured on the
// harmonic oscillator's closed form; "adaptive" is whether it runs without a step and meets
// a tolerance; "locates events" is whether it stops on a falling ball's floor crossing at the
// closed-form time. Then the readers of the table: the option checks' messages, the
// automatic choice (the rule documented in method_choice.hpp), `mbd simulate --help`, and the
// one stabilization parser.
#include "support/function_problem.hpp"
#include "support/test_support.hpp"

#include <mbd/formulation_setup.hpp>
#include <mbd/integrator.hpp>
#include <mbd/sdk/params.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace {

using Eigen::VectorXd;
using mbd::IntegratorDescription;
using mbd::test::FunctionProblem;
using mbd::test::run;

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

using mbd::test::oscillator_error;

// A ball dropped from 1 m: x'' = -g; the event is its height x, crossing zero at sqrt(2 / g).
class FallingBall : public FunctionProblem {
public:
    FallingBall()
        : FunctionProblem(2, [](double, const VectorXd& y, VectorXd& f) {
              f[0] = y[1];
              f[1] = -kG;
          }) {}
    int event_count() const override { return 1; }
    void event_values(double, const VectorXd& y, VectorXd& g) override {
        g.resize(1);
        g[0] = y[0];
    }
    static constexpr double kG = 9.81;
};

}  // namespace

TEST(IntegratorTable, EachIntegratorReportsItsRow) {
    ASSERT_FALSE(mbd::integrator_descriptions().empty());
    for (const IntegratorDescription& d : mbd::integrator_descriptions()) {
        const auto integrator = mbd::make_integrator(d.name, {});
        EXPECT_EQ(integrator->name(), d.name);
        EXPECT_EQ(integrator->adaptive(), d.adaptive) << d.name;
        EXPECT_EQ(integrator->needs_index3(), d.needs_index3) << d.name;
        EXPECT_EQ(integrator->locates_events(), d.locates_events) << d.name;
        EXPECT_EQ(&mbd::describe_integrator(d.name), &integrator->description()) << d.name;
        EXPECT_GE(d.order, 1) << d.name;
    }
}

// The order is what the error estimate's Richardson factor 2^p / (2^p - 1) reads.
TEST(IntegratorTable, FixedStepOrdersAreTheMeasuredOrders) {
    int measured = 0;
    for (const IntegratorDescription& d : mbd::integrator_descriptions()) {
        if (d.adaptive || d.needs_index3) continue;  // the index-3 one is measured on a DAE in test_integrators
        const double coarse = oscillator_error(d.name, 0.01), fine = oscillator_error(d.name, 0.005);
        const double order = std::log2(coarse / fine);
        std::printf("%s: error %.3e -> %.3e, order %.3f (described %d)\n", d.name, coarse, fine, order, d.order);
        EXPECT_NEAR(order, d.order, 0.25) << d.name;
        ++measured;
    }
    EXPECT_GE(measured, 2);  // euler, rk4
}

TEST(IntegratorTable, AdaptiveOnesMeetAToleranceWithoutAStepAndFixedStepOnesNeedOne) {
    // y' = -y + sin t, y(0) = 1: y = 1.5 e^-t + (sin t - cos t) / 2
    const auto exact = [](double t) { return 1.5 * std::exp(-t) + 0.5 * (std::sin(t) - std::cos(t)); };
    for (const IntegratorDescription& d : mbd::integrator_descriptions()) {
        if (d.needs_index3) continue;
        FunctionProblem problem(1, [](double t, const VectorXd& y, VectorXd& f) { f[0] = -y[0] + std::sin(t); });
        mbd::IntegratorSettings s;
        s.tolerance = 1e-8;
        if (!d.adaptive) {
            EXPECT_THROW(run(d.name, s, problem, 0.0, VectorXd::Ones(1), {2.0}), mbd::InputError) << d.name;
            continue;
        }
        const double y = run(d.name, s, problem, 0.0, VectorXd::Ones(1), {2.0}).y.back()[0];
        EXPECT_NEAR(y, exact(2.0), 1e-6) << d.name;
    }
}

TEST(IntegratorTable, ThoseThatLocateEventsStopOnTheBallsFloorCrossing) {
    const double crossing = std::sqrt(2.0 / FallingBall::kG);
    for (const IntegratorDescription& d : mbd::integrator_descriptions()) {
        if (d.needs_index3) continue;
        FallingBall ball;
        mbd::IntegratorSettings s;
        s.tolerance = 1e-9;
        if (!d.adaptive) s.step = 0.01;
        VectorXd y0(2);
        y0 << 1.0, 0.0;
        const auto integrator = mbd::make_integrator(d.name, s);
        mbd::IntegratorStats stats;
        integrator->begin(ball, 0.0, y0, 1.0, stats);
        double t_event = -1.0;
        while (integrator->time() < 1.0 - 1e-12) {
            integrator->step(1.0);
            if (stats.events > 0 && t_event < 0.0) t_event = integrator->time();
        }
        EXPECT_EQ(stats.events, d.locates_events ? 1 : 0) << d.name;
        if (d.locates_events) EXPECT_NEAR(t_event, crossing, 1e-6) << d.name;
    }
}

TEST(IntegratorTable, OptionMessagesListTheIntegratorsOfEachKind) {
    std::string step_refused, tol_refused, automatic;
    try {
        mbd::check_integrator_options("dopri5", false, 0.0, true, 1e-3, 1.0, mbd::command_line_spelling);
    } catch (const mbd::InputError& e) {
        step_refused = e.what();
    }
    try {
        mbd::check_integrator_options("rk4", true, 1e-6, false, 0.0, 1.0, mbd::command_line_spelling);
    } catch (const mbd::InputError& e) {
        tol_refused = e.what();
    }
    try {
        mbd::check_integrator_options("", false, 0.0, true, 1e-3, 1.0, mbd::command_line_spelling);
    } catch (const mbd::InputError& e) {
        automatic = e.what();
    }
    for (const IntegratorDescription& d : mbd::integrator_descriptions()) {
        EXPECT_EQ(contains(step_refused, d.name), !d.adaptive || d.name == std::string("dopri5")) << step_refused;
        EXPECT_EQ(contains(tol_refused, d.name), d.adaptive || d.name == std::string("rk4")) << tol_refused;
    }
    // method_choice.hpp: dop853 for a scene that is not stiff, cvode for a stiff one
    EXPECT_STREQ(mbd::automatic_integrator(false).name, "dop853");
    EXPECT_STREQ(mbd::automatic_integrator(true).name, "cvode");
    EXPECT_TRUE(contains(automatic, "the automatic integrator (dop853 or cvode)")) << automatic;
}

TEST(IntegratorTable, SimulateHelpListsEveryIntegrator) {
    const mbd::test::CommandResult r = mbd::test::run_mbd("simulate --help");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    for (const std::string& name : mbd::integrator_names()) EXPECT_TRUE(contains(r.out, name)) << name << "\n" << r.out;
}

TEST(Stabilization, OneParserForEveryName) {
    const std::vector<std::string> names = mbd::stabilization_names();
    ASSERT_EQ(names, (std::vector<std::string>{"projection", "baumgarte", "none"}));
    EXPECT_EQ(mbd::parse_stabilization("projection"), mbd::Stabilization::Projection);
    EXPECT_EQ(mbd::parse_stabilization("baumgarte"), mbd::Stabilization::Baumgarte);
    EXPECT_EQ(mbd::parse_stabilization("none"), mbd::Stabilization::None);
    try {
        mbd::parse_stabilization("baumgart");
        FAIL() << "no InputError";
    } catch (const mbd::InputError& e) {
        EXPECT_TRUE(contains(e.what(), "'stabilization' must be projection, baumgarte or none, got 'baumgart'"))
            << e.what();
    }
}

TEST(Stabilization, TheCommandLineRefusesAnUnknownName) {
    const mbd::test::CommandResult r =
        mbd::test::run_mbd("simulate " + mbd::test::scene_path("four-bar.yaml").string() +
                           " --t-end 0.1 -o unwritten.csv --stabilization baumgart");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_TRUE(contains(r.err, "baumgarte")) << r.err;
}
