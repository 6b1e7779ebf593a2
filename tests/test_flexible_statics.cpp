// Statics with flexible bodies (`mbd statics`, the Ipopt plugin; issue 40): the equilibrium of
// ANCF cables against solutions computed here, independently of the engine.
// - The elastica: a cantilever clamped at node 0 under a dead tip load P perpendicular to it.
//   Oracle: the inextensible elastica EI theta'' = P cos(theta), theta(0) = 0, theta'(L) = 0
//   (theta the tangent's angle, s the arc length), solved by shooting on theta'(0) with RK4,
//   the tip at the integral of (cos theta, sin theta); its small-load limit P L^3 / (3 EI).
// - The catenary: a cable pinned at both ends hanging under its weight. Oracle:
//   y = a cosh((x - S/2) / a) - a cosh(S / (2a)), with a from the length, L = 2 a sinh(S / (2a)).
// Both cables are nearly inextensible (EA / P and EA / (rho A g a) of 1e6 or more) and the
// catenary's nearly without bending stiffness, so the closed forms hold to well below the bounds.
#include "support/newton_equilibrium.hpp"
#include "support/test_support.hpp"

#include <mbd/statics_analysis.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>

#include <array>
#include <cmath>
#include <functional>
#include <string>

namespace mbd {
namespace {

// ---------------------------------------------------------------- the elastica

struct Tip {
    double x = 0.0, y = 0.0;   // the tip's position
    double curvature = 0.0;    // theta'(L), zero at the solution
};

// Integrates EI theta'' = P cos(theta) from s = 0 (theta = 0, theta' = -k0) to L by RK4.
Tip integrate_elastica(double alpha, double k0, int steps = 4000) {
    // units L = 1, EI = 1: the load is alpha = P L^2 / EI
    using Y = std::array<double, 4>;  // theta, theta', x, y
    auto f = [&](const Y& y) { return Y{y[1], alpha * std::cos(y[0]), std::cos(y[0]), std::sin(y[0])}; };
    Y y{0.0, -k0, 0.0, 0.0};
    const double h = 1.0 / steps;
    for (int i = 0; i < steps; ++i) {
        Y k1 = f(y), s2, s3, s4;
        for (int j = 0; j < 4; ++j) s2[j] = y[j] + 0.5 * h * k1[j];
        const Y k2 = f(s2);
        for (int j = 0; j < 4; ++j) s3[j] = y[j] + 0.5 * h * k2[j];
        const Y k3 = f(s3);
        for (int j = 0; j < 4; ++j) s4[j] = y[j] + h * k3[j];
        const Y k4 = f(s4);
        for (int j = 0; j < 4; ++j) y[j] += h / 6 * (k1[j] + 2 * k2[j] + 2 * k3[j] + k4[j]);
    }
    return {y[2], y[3], y[1]};
}

// The elastica's tip (units L = 1, EI = 1) by bisection on the root curvature k0 in [0, alpha]:
// the moment at the root is P x_tip <= P L.
Tip elastica_tip(double alpha) {
    double lo = 0.0, hi = alpha;
    for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (lo + hi);
        (integrate_elastica(alpha, mid).curvature > 0 ? lo : hi) = mid;
    }
    return integrate_elastica(alpha, 0.5 * (lo + hi));
}

// The same tip by the classical incomplete elliptic integral relations (the first integral
// EI theta'^2 / 2 = P (sin phi0 - sin phi), phi = -theta, phi0 the tip's rotation, substituted by
// 1 + sin phi = 2 k^2 sin^2 psi): sqrt(alpha) = K(k) - F(k, psi1), k^2 = (1 + sin phi0) / 2,
// sin psi1 = 1 / (k sqrt 2); tip deflection 1 - 2 (E(k) - E(k, psi1)) / sqrt(alpha) and tip
// abscissa sqrt(2 sin phi0 / alpha).
Tip elliptic_tip(double alpha) {
    auto parts = [](double phi0, double& k, double& psi1) {
        k = std::sqrt((1 + std::sin(phi0)) / 2);
        psi1 = std::asin(1 / (k * std::sqrt(2.0)));
    };
    double lo = 0.0, hi = M_PI / 2, k = 0, psi1 = 0;
    for (int i = 0; i < 100; ++i) {  // the load grows with the tip's rotation
        const double mid = 0.5 * (lo + hi);
        parts(mid, k, psi1);
        (std::comp_ellint_1(k) - std::ellint_1(k, psi1) < std::sqrt(alpha) ? lo : hi) = mid;
    }
    const double phi0 = 0.5 * (lo + hi);
    parts(phi0, k, psi1);
    return {std::sqrt(2 * std::sin(phi0) / alpha),
            -(1 - 2 * (std::comp_ellint_2(k) - std::ellint_2(k, psi1)) / std::sqrt(alpha)), 0.0};
}

TEST(FlexibleStatics, TheShootingAndTheEllipticIntegralsGiveTheSameElastica) {
    for (const double alpha : {1e-2, 1.0, 3.0, 10.0}) {
        const Tip shot = elastica_tip(alpha), elliptic = elliptic_tip(alpha);
        std::printf("elastica P L^2/EI = %g: shooting (%.12f, %.12f), elliptic (%.12f, %.12f)\n", alpha, shot.x,
                    shot.y, elliptic.x, elliptic.y);
        EXPECT_NEAR(shot.x, elliptic.x, 1e-9) << alpha;
        EXPECT_NEAR(shot.y, elliptic.y, 1e-9) << alpha;
        EXPECT_LT(std::abs(shot.curvature), 1e-9);
    }
    // the small-load limit P L^3 / (3 EI), to its first nonlinear correction's order alpha^2
    EXPECT_NEAR(-elastica_tip(1e-3).y, 1e-3 / 3, 1e-3 / 3 * 1e-5);
}

// A cantilever of length 1 along x, EI = 1 N m^2, EA = 1e7 N, clamped at node 0, the load at its
// last node.
std::string cantilever(int elements, double P) {
    return "dimension: planar\nflexible_bodies:\n"
           "  - {name: beam, type: ancf_cable, from: [0, 0], to: [1, 0], elements: " + std::to_string(elements) +
           ", modulus: 1.0e9, area: 1.0e-2, second_moment: 1.0e-9, density: 1.0, axial_points: 2}\n"
           "joints:\n  - {name: clamp, type: fixed, bodies: [ground, {body: beam, node: 0}]}\n"
           "forces:\n  - {name: load, type: point_force, body: {body: beam, node: " + std::to_string(elements) +
           "}, force: [0, " + test::g17(-P) + "]}\n";
}

StaticsOptions options_without_stability() {
    StaticsOptions options;
    options.analyse_stability = false;
    return options;
}

StaticsResult solve(const Model& model) {
    const StaticsReport report = run_statics(model, test::shared_registry(), options_without_stability());
    EXPECT_TRUE(report.result.converged) << report.result.status << ": " << report.result.message;
    return report.result;
}

// The elastica at P L^2 / EI up to 10, the engine's ANCF model solved by the test's own Newton
// iteration on its forces, stiffness and constraints, the load raised in steps from the straight
// beam (each step starting from the last equilibrium): an independent solver of the same model,
// beside `mbd statics` (Ipopt) below.
TEST(FlexibleStatics, ACantileverUnderATipLoadFollowsTheElastica) {
    const int elements = 16;
    const int tip = 4 * elements;  // the last node's position in the beam's coordinates
    const Model straight = test::scene(cantilever(elements, 0.0));
    State state = straight.initial_state();
    double reached = 0.0;
    for (const double alpha : {1.0, 3.0, 10.0}) {
        const int steps = 10;
        double residual = 0.0;
        for (int k = 1; k <= steps; ++k) {
            const double load = reached + (alpha - reached) * k / steps;
            const Model loaded = test::scene(cantilever(elements, load));
            ModelSystem system(loaded);
            state = test::newton_equilibrium(system, state, residual);
            // the force residual stalls at the round-off of the axial forces (EA 1e7 N times a
            // strain resolved to 1e-15), far below the load
            ASSERT_LT(residual, 1e-6 * std::max(1.0, load)) << "load " << load;
        }
        reached = alpha;
        const Model model = test::scene(cantilever(elements, alpha));
        const int o = model.flexible_bodies.front().offset + tip;
        const Tip oracle = elastica_tip(alpha);
        const double dx = state.q[o] - oracle.x, dy = state.q[o + 1] - oracle.y;
        std::printf("elastica P L^2/EI = %g: tip (%.8f, %.8f), oracle (%.8f, %.8f), error %.3g, residual %.3g\n",
                    alpha, state.q[o], state.q[o + 1], oracle.x, oracle.y, std::hypot(dx, dy), residual);
        EXPECT_LT(std::hypot(dx, dy), 1e-4 * -oracle.y) << alpha;
    }
}

TEST(FlexibleStatics, MbdStaticsGivesTheSmallLoadLimit) {
    const int elements = 16, tip = 4 * elements;
    const double alpha = 1e-3;
    const Model model = test::scene(cantilever(elements, alpha));
    const StaticsResult r = solve(model);
    const int o = model.flexible_bodies.front().offset + tip;
    const Tip oracle = elastica_tip(alpha);
    std::printf("statics, P L^2/EI = %g: tip (%.10f, %.10f), oracle (%.10f, %.10f), P L^3/(3EI) %.10f; %d iterations\n",
                alpha, r.state.q[o], r.state.q[o + 1], oracle.x, oracle.y, alpha / 3, r.iterations);
    EXPECT_LT(std::hypot(r.state.q[o] - oracle.x, r.state.q[o + 1] - oracle.y), 1e-4 * -oracle.y);
    EXPECT_NEAR(-r.state.q[o + 1], alpha / 3, 1e-4 * alpha / 3);  // P L^3 / (3 EI)
}

// The same elastica by `mbd statics`' own solver (the Ipopt plugin through run_statics, as the
// command runs it): the dead tip load is conservative (potential -F . r_tip), so the potential is
// minimised with the exact Hessian, from the straight beam in one solve per load. The clamp's
// reaction (on the beam's material frame at node 0) balances the load.
TEST(FlexibleStatics, MbdStaticsFollowsTheElasticaUnderLargeTipLoads) {
    const int elements = 16, tip = 4 * elements;
    for (const double alpha : {1.0, 3.0, 10.0}) {
        const Model model = test::scene(cantilever(elements, alpha));
        const StaticsReport report = run_statics(model, test::shared_registry(), options_without_stability());
        const StaticsResult& r = report.result;
        ASSERT_TRUE(r.converged) << r.status << ": " << r.message;
        EXPECT_EQ(r.objective, "potential");
        const int o = model.flexible_bodies.front().offset + tip;
        const Tip oracle = elastica_tip(alpha);
        const double error = std::hypot(r.state.q[o] - oracle.x, r.state.q[o + 1] - oracle.y);
        std::printf("statics, P L^2/EI = %g: tip (%.8f, %.8f), oracle (%.8f, %.8f), error %.3g; %d iterations\n",
                    alpha, r.state.q[o], r.state.q[o + 1], oracle.x, oracle.y, error, r.iterations);
        EXPECT_LT(error, 1e-4 * -oracle.y) << alpha;
        // the clamp holds the whole beam: the load P up and its moment P x_tip (exact equilibrium,
        // at the tip the solver reached), on the beam at node 0
        ASSERT_EQ(report.reactions.size(), 1u);
        const JointLoad& clamp = report.reactions[0];
        const double x_tip = r.state.q[o];
        std::printf("  clamp: F = (%.3g, %.12f), T = %.12f, P x_tip = %.12f\n", clamp.force.x(), clamp.force.y(),
                    clamp.torque.z(), alpha * x_tip);
        EXPECT_NEAR(clamp.force.x(), 0.0, 1e-7 * alpha);
        EXPECT_NEAR(clamp.force.y(), alpha, 1e-7 * alpha);
        EXPECT_NEAR(clamp.torque.z(), alpha * x_tip, 1e-7 * alpha);
    }
}

// ---------------------------------------------------------------- the catenary

// The catenary parameter a of a chain of length L over a span S: L = 2 a sinh(S / (2a)), by
// bisection (L / S - 1 decreases from infinity to 0 as a grows).
double catenary_parameter(double S, double L) {
    double lo = 1e-3 * S, hi = 1e3 * S;
    for (int i = 0; i < 200; ++i) {
        const double mid = std::sqrt(lo * hi);
        (2 * mid * std::sinh(S / (2 * mid)) > L ? lo : hi) = mid;
    }
    return std::sqrt(lo * hi);
}

TEST(FlexibleStatics, ACableHangingBetweenTwoPinsIsACatenary) {
    // a cable of length 1.2 meshed straight along x, pinned at (0, 0); its far end pinned to an
    // anchor that a driven slider brings to x = S = 1 at t = 1 (the time of the analysis)
    const double S = 1.0, L = 1.2;
    const int elements = 24;
    const std::string scene =
        "dimension: planar\ngravity: [0, -9.81]\nflexible_bodies:\n"
        "  - {name: rope, type: ancf_cable, from: [0, 0], to: [1.2, 0], elements: " + std::to_string(elements) +
        ", modulus: 1.0e9, area: 1.0e-2, second_moment: 1.0e-15, density: 100}\n"
        "bodies:\n  - {name: anchor, mass: 1, inertia: 1, position: [1.2, 0]}\n"
        "joints:\n"
        "  - {name: left, type: revolute, bodies: [ground, {body: rope, node: 0}]}\n"
        "  - {name: right, type: revolute, bodies: [anchor, {body: rope, node: " + std::to_string(elements) + "}]}\n"
        "  - {name: slide, type: prismatic, bodies: [ground, anchor], axis: [1, 0]}\n"
        "drivers:\n  - {name: pull, joint: slide, motion: {type: linear, initial: 0, rate: -0.2}}\n";
    const Model model = test::scene(scene);
    StaticsOptions options;
    options.time = 1.0;
    options.analyse_stability = false;
    const StaticsReport report = run_statics(model, test::shared_registry(), options);
    ASSERT_TRUE(report.result.converged) << report.result.status << ": " << report.result.message;
    const double a = catenary_parameter(S, L), sag = a * (std::cosh(S / (2 * a)) - 1);
    const int o = model.flexible_bodies.front().offset;
    double worst = 0.0, lowest = 0.0;
    for (int k = 0; k <= elements; ++k) {
        const double x = report.result.state.q[o + 4 * k], y = report.result.state.q[o + 4 * k + 1];
        worst = std::max(worst, std::abs(y - (a * std::cosh((x - S / 2) / a) - a * std::cosh(S / (2 * a)))));
        lowest = std::min(lowest, y);
    }
    std::printf("catenary: a = %.8f, sag %.8f, cable's lowest node %.8f, largest node error %.3g; %d iterations\n", a,
                sag, lowest, worst, report.result.iterations);
    EXPECT_LT(worst, 1e-5);
    EXPECT_NEAR(-lowest, sag, 1e-5);  // node 12 is the middle
    // the pins' reactions on the cable: the catenary's horizontal tension H = w a (w = rho A g the
    // weight per length) pulling outwards, and half the weight w L each
    const double w = 100 * 1.0e-2 * 9.81, H = w * a;
    ASSERT_EQ(report.reactions.size(), 3u);
    const JointLoad &left = report.reactions[0], &right = report.reactions[1];
    std::printf("catenary pins: left (%.8f, %.8f), right (%.8f, %.8f); H = %.8f, w L / 2 = %.8f\n", left.force.x(),
                left.force.y(), right.force.x(), right.force.y(), H, w * L / 2);
    EXPECT_NEAR(left.force.x(), -H, 1e-4 * H);
    EXPECT_NEAR(right.force.x(), H, 1e-4 * H);
    EXPECT_NEAR(left.force.y(), w * L / 2, 1e-6 * w * L);
    EXPECT_NEAR(right.force.y(), w * L / 2, 1e-6 * w * L);
}

TEST(FlexibleStatics, MbdStaticsReportsTheNodesAndRefusesToWriteADeformedScene) {
    const auto dir = test::scratch("flexible_statics_cli");
    const auto scene = test::write_text(dir / "cantilever.yaml", cantilever(8, 0.01));
    const test::CommandResult json = test::run_mbd("statics " + scene.string() + " --json");
    ASSERT_EQ(json.exit_code, 0) << json.err;
    const auto doc = nlohmann::json::parse(json.out);
    const auto& nodes = doc.at("flexible_bodies").at("beam").at("nodes");
    ASSERT_EQ(nodes.size(), 9u);
    const Tip oracle = elliptic_tip(0.01);
    // 8 elements: the mesh's own error at P L^2 / EI = 0.01 is below 1e-4 of the deflection
    EXPECT_NEAR(nodes[8][0].get<double>(), oracle.x, 1e-4 * -oracle.y);
    EXPECT_NEAR(nodes[8][1].get<double>(), oracle.y, 1e-4 * -oracle.y);
    EXPECT_NEAR(nodes[0][0].get<double>(), 0.0, 1e-12);
    // the clamp carries the tip load 0.01 and its moment 0.01 x_tip
    EXPECT_NEAR(doc.at("reactions").at("clamp").at("fy").get<double>(), 0.01, 1e-9);
    EXPECT_NEAR(doc.at("reactions").at("clamp").at("tz").get<double>(), 0.01 * nodes[8][0].get<double>(), 1e-9);
    const auto output = dir / "equilibrium.yaml";
    const test::CommandResult refused = test::run_mbd("statics " + scene.string() + " --output " + output.string());
    EXPECT_EQ(refused.exit_code, 2);
    EXPECT_NE(refused.err.find("flexible body 'beam'"), std::string::npos) << refused.err;
    EXPECT_FALSE(std::filesystem::exists(output));
}

}  // namespace
}  // namespace mbd
