// Modes of flexible bodies (`mbd modes`, issue 40): an ANCF cantilever, clamped at its node 0 by
// a `fixed` joint, against the Euler-Bernoulli cantilever's natural frequencies
//     omega_i = (beta_i L)^2 sqrt(EI / (rho A L^4)),
// beta_1 L = 1.875104068711961, beta_2 L = 4.694091132974175 (the roots of cos x cosh x = -1),
// converging as elements are added at the cubic Hermite element's order h^4 (the rate observed
// from 2, 4, 8, 16 elements in the test); and the same through the `mbd modes` command.
#include "support/test_support.hpp"

#include <mbd/linearisation.hpp>
#include <mbd/model_system.hpp>
#include <mbd/modes.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace mbd {
namespace {

// rho A = 1 kg/m, EI = 10 N m^2, EA = 1e4 N, L = 1 m: the first axial frequency
// (pi / 2) sqrt(EA / rho A) / L = 157 rad/s lies above the second bending one (69.7 rad/s), so
// the two lowest modes are the first two bending modes.
constexpr double kRhoA = 1.0, kEI = 10.0, kLength = 1.0;
constexpr double kBetaL[2] = {1.875104068711961, 4.694091132974175};

double euler_bernoulli(int mode) {
    return kBetaL[mode] * kBetaL[mode] * std::sqrt(kEI / (kRhoA * std::pow(kLength, 4)));
}

std::string cantilever(int elements) {
    return "dimension: planar\nflexible_bodies:\n"
           "  - {name: beam, type: ancf_cable, from: [0, 0], to: [" + test::g17(kLength) + ", 0], elements: " +
           std::to_string(elements) + ", modulus: 1.0e4, area: 1.0, second_moment: 1.0e-3, density: 1.0}\n"
           "joints:\n  - {name: clamp, type: fixed, bodies: [ground, {body: beam, node: 0}]}\n";
}

// The natural frequencies of the cantilever's modes, lowest first.
std::vector<double> frequencies(int elements, LinearModel* linear_out = nullptr) {
    const Model model = test::scene(cantilever(elements));
    ModelSystem system(model);
    // the straight mesh's elastic forces are zero up to round-off, which the stiffness of the
    // short elements' slopes turns into accelerations of up to about 1e-7 at 16 elements
    LinearisationOptions options;
    options.residual_tolerance = 1e-6;
    const LinearModel linear = linearise(system, model.initial_state(), {}, options);
    const ModeAnalysis analysis = modes_of(linear);
    std::vector<double> out;
    for (const Mode& m : analysis.modes) {
        EXPECT_TRUE(m.oscillatory) << elements << " elements: a mode that does not oscillate";
        EXPECT_LT(std::abs(m.damping_ratio), 1e-8) << elements << " elements: damping without any damper";
        out.push_back(m.natural_frequency);
    }
    EXPECT_TRUE(analysis.ignorable.empty());
    if (linear_out) *linear_out = linear;
    return out;
}

TEST(FlexibleModes, AnAncfCantileverConvergesToTheEulerBernoulliFrequenciesAtTheElementsOrder) {
    const std::vector<int> meshes{2, 4, 8, 16};
    std::vector<std::vector<double>> error(2);
    for (int elements : meshes) {
        LinearModel linear;
        const std::vector<double> omega = frequencies(elements, &linear);
        // 4 coordinates per node, 3 taken by the clamp: every other one is a mode
        ASSERT_EQ(linear.coordinates.size(), static_cast<size_t>(4 * (elements + 1) - 3));
        ASSERT_EQ(omega.size(), linear.coordinates.size());
        for (int i = 0; i < 2; ++i) {
            error[i].push_back(omega[i] / euler_bernoulli(i) - 1.0);
            // a conforming mesh (consistent mass, exact stiffness) bounds the frequencies from above
            EXPECT_GT(error[i].back(), 0.0) << "mode " << i + 1 << ", " << elements << " elements";
            std::printf("%2d elements: mode %d omega %.12f rad/s, relative error %.3e\n", elements, i + 1, omega[i],
                        error[i].back());
        }
    }
    for (int i = 0; i < 2; ++i)
        for (size_t k = 0; k + 1 < meshes.size(); ++k) {
            const double rate = std::log2(error[i][k] / error[i][k + 1]);
            std::printf("mode %d, %d -> %d elements: observed rate %.3f\n", i + 1, meshes[k], meshes[k + 1], rate);
            // the cubic element's h^4 once the mesh resolves the mode (the second mode's half
            // wave is about two elements long at 2 elements: pre-asymptotic there)
            if (meshes[k] >= 4)
                EXPECT_NEAR(rate, 4.0, 0.3) << "mode " << i + 1 << ", " << meshes[k] << " -> " << meshes[k + 1];
            else
                EXPECT_GT(rate, 2.5) << "mode " << i + 1 << ", " << meshes[k] << " -> " << meshes[k + 1];
        }
    EXPECT_LT(error[0].back(), 1e-6);
    EXPECT_LT(error[1].back(), 1e-5);
}

TEST(FlexibleModes, TheCommandWritesTheCantileversModesWithTheBodysCoordinates) {
    const std::filesystem::path dir = test::scratch("flexible_modes_cli");
    const std::filesystem::path scene = test::write_text(dir / "cantilever.yaml", cantilever(8));
    const std::filesystem::path csv = dir / "modes.csv";
    const test::CommandResult r =
        test::run_mbd("modes '" + scene.string() + "' --about initial --residual-tolerance 1e-6 --output '" + csv.string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const test::Csv table = test::read_csv(csv);
    ASSERT_EQ(table.rows.size(), 4u * 9u - 3u);
    // the library's frequencies (the test above bounds their error), and the columns of the
    // beam's coordinates by the body's own names
    const std::vector<double> omega = frequencies(8);
    for (int i = 0; i < 2; ++i) {
        const double written = table.rows[i][table.column("natural_frequency_rad_s")];
        EXPECT_NEAR(written, omega[i], 1e-9 * omega[i]);
        EXPECT_NEAR(written, euler_bernoulli(i), 1e-4 * euler_bernoulli(i));
    }
    EXPECT_GE(table.column("beam.node8_y_re"), 0);
    EXPECT_GE(table.column("beam.node8_slope_y_re"), 0);
}

}  // namespace
}  // namespace mbd
