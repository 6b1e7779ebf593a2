// `mbd statics` with a floating-frame body (issue 40): a cantilever ffrf_body (EI = 1, rho A = 1,
// L = 1; 100 elements, 4 modes) clamped at its frame, under a small dead tip load P and under its
// weight. The body is linear in its modal coordinates, so its equilibrium is the 4-mode truncated
// modal sum. Oracle, computed here independently of the plugin: the Euler-Bernoulli clamped-free
// modes phi_i(x) = cosh b x - cos b x - s (sinh b x - sin b x), s = (cosh b L + cos b L) /
// (sinh b L + sin b L), with b_i L the roots of cos x cosh x = -1 (Newton from (2i - 1) pi / 2),
// their mass m_i = rho A int phi_i^2, stiffness k_i = EI b_i^4 int phi_i^2 and load integral
// int phi_i (Gauss-Legendre):
//   tip load:     w(L) = sum_i phi_i(L)^2 P / k_i,         coordinate p_i = P phi_i(L) / (k_i / sqrt(m_i))
//   uniform load: w(L) = sum_i phi_i(L) w int phi_i / k_i
// and the series' limits P L^3 / (3 EI) and w L^4 / (8 EI) with bounds on the remainder (below).
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

namespace mbd {
namespace {

namespace fs = std::filesystem;
const double kPi = std::acos(-1.0);
constexpr int kModes = 4;

// b_i L, the i-th root (i from 1) of cos x cosh x + 1 = 0, by Newton from (2i - 1) pi / 2.
double root(int i) {
    double x = (2 * i - 1) * kPi / 2;
    for (int k = 0; k < 50; ++k)
        x -= (std::cos(x) * std::cosh(x) + 1) / (std::cos(x) * std::sinh(x) - std::sin(x) * std::cosh(x));
    return x;
}

struct Mode {
    double beta = 0, tip = 0, mass = 0, integral = 0, stiffness = 0;
};

// The i-th Euler-Bernoulli clamped-free mode of the unit beam (L = EI = rho A = 1), its integrals
// by 5-point Gauss-Legendre over 40 panels (phi is smooth: far below the asserted 1e-8).
Mode mode(int i) {
    static const double xi[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831, 0.9061798459386640};
    static const double w[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889, 0.4786286704993665,
                                0.2369268850561891};
    Mode m;
    m.beta = root(i);
    const double b = m.beta, s = (std::cosh(b) + std::cos(b)) / (std::sinh(b) + std::sin(b));
    auto phi = [&](double x) { return std::cosh(b * x) - std::cos(b * x) - s * (std::sinh(b * x) - std::sin(b * x)); };
    const int panels = 40;
    for (int k = 0; k < panels; ++k)
        for (int g = 0; g < 5; ++g) {
            const double x = (k + 0.5 + 0.5 * xi[g]) / panels, dx = 0.5 * w[g] / panels;
            m.mass += dx * phi(x) * phi(x);
            m.integral += dx * phi(x);
        }
    m.tip = phi(1.0);
    m.stiffness = std::pow(b, 4) * m.mass;
    return m;
}

struct Statics {
    nlohmann::json report;
    double tip = 0;  // the tip node's y
};

Statics run_statics(const std::string& name, const std::string& extra) {
    const fs::path dir = test::scratch("ffrf_statics_" + name);
    const fs::path scene = test::write_text(
        dir / "cantilever.yaml",
        "dimension: planar\n" + extra +
            "flexible_bodies:\n  - {name: blade, type: ffrf_body, from: [0, 0], to: [1, 0], elements: 100, modes: 4, "
            "modulus: 1.0e6, area: 1.0, second_moment: 1.0e-6, density: 1.0}\n"
            "joints:\n  - {name: clamp, type: fixed, bodies: [ground, {body: blade, at: 0}]}\n");
    const test::CommandResult r = test::run_mbd("statics '" + scene.string() + "' --json");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    Statics out;
    out.report = nlohmann::json::parse(r.out);
    EXPECT_TRUE(out.report["converged"].get<bool>());
    out.tip = out.report["flexible_bodies"]["blade"]["nodes"].back()[1].get<double>();
    return out;
}

TEST(FfrfStatics, ATipLoadedCantileverRestsAtTheTruncatedModalSum) {
    const double P = 1e-3;
    const Statics s = run_statics("tip", "forces:\n  - {name: load, type: point_force, body: {body: blade, at: 1}, "
                                         "force: [0, -0.001]}\n");
    double modal = 0;
    for (int i = 1; i <= kModes; ++i) {
        const Mode m = mode(i);
        modal -= m.tip * m.tip * P / m.stiffness;
        // the reported modal coordinate of the mass-normalized mode (the plugin's sign: the tip moves
        // +y) and the reduced Hessian's eigenvalues, the modal stiffnesses omega_i^2 = EI b_i^4 / (rho A):
        // each mode alone carries the mesh's discretisation error (h^4: 2e-7 for mode 4's omega^2 at
        // 100 elements), hence 1e-6 here; the tip's sum is dominated by mode 1 (1e-8 below).
        const double p = -P * std::abs(m.tip) / std::sqrt(m.mass) / (m.stiffness / m.mass);
        const double reported = s.report["flexible_bodies"]["blade"]["coordinates"]["mode" + std::to_string(i)];
        EXPECT_NEAR(reported, p, 1e-6 * std::abs(p)) << "mode " << i;
        EXPECT_NEAR(s.report["tangent_eigenvalues"][i - 1].get<double>(), std::pow(m.beta, 4), 1e-6 * std::pow(m.beta, 4));
    }
    // The series' remainder: with phi_i(L)^2 / int phi_i^2 = 4 for every mode, P L^3 / (3 EI) -
    // w_4(L) = 4 P sum_{i>4} 1 / b_i^4. For i > 4, |b_i - (2i - 1) pi / 2| < 0.01, and f(i) =
    // (pi (2i - 1) / 2 -+ 0.01)^-4 is convex and decreasing, so the sum lies between the
    // integrals of f from 5 and from 4.5: 1 / (3 pi u^3) at u = 9 pi / 2 + 0.01 and 4 pi - 0.01.
    EXPECT_LT(std::abs(root(5) - 9 * kPi / 2), 0.01);
    const double lower = 4 * P / (3 * kPi * std::pow(9 * kPi / 2 + 0.01, 3));
    const double upper = 4 * P / (3 * kPi * std::pow(4 * kPi - 0.01, 3));
    const double closed = -P / 3, remainder = s.tip - closed;
    std::printf("tip load: tip %.12g, 4-mode sum %.12g (relative %.2e); P L^3 / 3EI %.12g, remainder %.4g in "
                "[%.4g, %.4g]; clamp F %.10g, T %.10g\n", s.tip, modal, s.tip / modal - 1, closed, remainder, lower,
                upper, s.report["reactions"]["clamp"]["fy"].get<double>(), s.report["reactions"]["clamp"]["tz"].get<double>());
    EXPECT_NEAR(s.tip, modal, 1e-8 * std::abs(modal));
    EXPECT_GT(remainder, lower);
    EXPECT_LT(remainder, upper);
    // the clamp carries the load and its moment P L
    EXPECT_NEAR(s.report["reactions"]["clamp"]["fy"].get<double>(), P, 1e-12);
    EXPECT_NEAR(s.report["reactions"]["clamp"]["tz"].get<double>(), P * 1.0, 1e-12);
}

TEST(FfrfStatics, ACantileverUnderItsWeightRestsAtTheTruncatedModalSum) {
    const double w = 1e-3;  // rho A g
    const Statics s = run_statics("weight", "gravity: [0, -0.001]\n");
    double modal = 0;
    for (int i = 1; i <= kModes; ++i) {
        const Mode m = mode(i);
        modal -= m.tip * w * m.integral / m.stiffness;
    }
    // The series sum_i phi_i(L) int phi_i / k_i alternates in sign with terms decreasing in size
    // (4 s_i / b_i^5), so the remainder after mode 4 lies between 0 and the fifth term.
    const Mode fifth = mode(5);
    const double bound = w * std::abs(fifth.tip * fifth.integral / fifth.stiffness);
    const double closed = -w / 8, remainder = s.tip - closed;
    std::printf("weight: tip %.12g, 4-mode sum %.12g (relative %.2e); w L^4 / 8EI %.12g, remainder %.4g in (0, %.4g); "
                "clamp F %.10g, T %.10g\n", s.tip, modal, s.tip / modal - 1, closed, remainder, bound,
                s.report["reactions"]["clamp"]["fy"].get<double>(), s.report["reactions"]["clamp"]["tz"].get<double>());
    EXPECT_NEAR(s.tip, modal, 1e-8 * std::abs(modal));
    EXPECT_GT(remainder, 0.0);
    EXPECT_LT(remainder, bound);
    EXPECT_NEAR(s.report["reactions"]["clamp"]["fy"].get<double>(), w * 1.0, 1e-12);
    EXPECT_NEAR(s.report["reactions"]["clamp"]["tz"].get<double>(), w * 0.5, 1e-12);
}

}  // namespace
}  // namespace mbd
