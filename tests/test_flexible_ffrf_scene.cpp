// The floating-frame body (ffrf_body) inside scenes (issue 40): its mass matrix varies with its
// coordinates (the frame's angle and the modal coordinates couple), so the augmented
// formulation re-evaluates and re-factors its block at every state (kit varying_mass.hpp) while
// the constant blocks stay factored once. Oracles:
//  - clamped at its frame by a `fixed` joint, `mbd modes` gives the Euler-Bernoulli cantilever's
//    frequencies omega_i = (beta_i L)^2 sqrt(EI / (rho A L^4)) to 1e-6 with 4 modes of a
//    100-element beam (beta_i L the roots of cos x cosh x = -1);
//  - pinned at its frame and released horizontal under gravity, it conserves energy (no
//    dissipation anywhere) to the integrator's tolerance, and its pin holds.
#include "support/test_support.hpp"

#include <mbd/linearisation.hpp>
#include <mbd/model_system.hpp>
#include <mbd/modes.hpp>
#include <mbd/simulation.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace mbd {
namespace {

// EI = 1 N m^2, rho A = 1 kg/m, L = 1 m
std::string beam(const std::string& joint) {
    return "dimension: planar\ngravity: [0, -9.81]\nflexible_bodies:\n"
           "  - {name: blade, type: ffrf_body, from: [0, 0], to: [1, 0], elements: 100, modes: 4, modulus: 1.0e6, "
           "area: 1.0, second_moment: 1.0e-6, density: 1.0}\n"
           "joints:\n  - {name: hub, type: " + joint + ", bodies: [ground, {body: blade, at: 0}]}\n";
}

TEST(FlexibleFfrfScene, AClampedFfrfBeamGivesTheEulerBernoulliFrequenciesThroughModes) {
    // no gravity: the straight beam is the equilibrium
    std::string text = beam("fixed");
    text.replace(text.find("gravity: [0, -9.81]\n"), 20, "");
    const Model model = test::scene(text);
    ModelSystem system(model);
    const LinearModel linear = linearise(system, model.initial_state(), {});
    ASSERT_EQ(linear.coordinates.size(), 4u);
    EXPECT_EQ(linear.coordinates[0], "blade.mode1");
    const ModeAnalysis analysis = modes_of(linear);
    ASSERT_EQ(analysis.modes.size(), 4u);
    const double beta_l[4] = {1.875104068711961, 4.694091132974175, 7.854757438237613, 10.99554073487547};
    for (int i = 0; i < 4; ++i) {
        const double exact = beta_l[i] * beta_l[i];
        const double omega = analysis.modes[i].natural_frequency;
        std::printf("mode %d: omega %.12f rad/s, Euler-Bernoulli %.12f, relative error %.2e\n", i + 1, omega, exact,
                    omega / exact - 1);
        EXPECT_TRUE(analysis.modes[i].oscillatory);
        EXPECT_NEAR(omega, exact, 1e-6 * exact) << "mode " << i + 1;
    }
}

TEST(FlexibleFfrfScene, APinnedFfrfPendulumKeepsItsEnergyAndItsPin) {
    const Model model = test::scene(beam("revolute"));
    SimulationSettings settings = test::adaptive_run("augmented", "dopri5", 1e-9, 1.0, 0.02);
    settings.diagnostics = true;
    std::vector<std::string> columns;
    std::vector<std::vector<double>> rows;
    const SimulationResult result =
        simulate(model, test::shared_registry(), settings, [&](const SimulationSample& s) {
            rows.push_back(*s.row);
            return true;
        });
    columns = result.columns;
    auto column = [&](const std::string& name) {
        return static_cast<size_t>(std::find(columns.begin(), columns.end(), name) - columns.begin());
    };
    ASSERT_EQ(rows.size(), 51u);
    const size_t T = column("kinetic_energy"), V = column("potential_energy");
    ASSERT_LT(T, columns.size());
    double drift = 0.0, fallen = 0.0;
    for (const auto& row : rows) {
        drift = std::max(drift, std::abs(row[T] + row[V] - rows[0][T] - rows[0][V]));
        fallen = std::max(fallen, rows[0][V] - row[V]);
    }
    // m g L / 2 = 4.905 J is released in the first quarter swing
    const double scale = 9.81 * 1.0 * 0.5;
    std::printf("energy drift %.3g J of %.3g J released\n", drift, fallen);
    EXPECT_GT(fallen, 0.5 * scale);
    EXPECT_LT(drift, 10 * 1e-9 * scale);
}

}  // namespace
}  // namespace mbd
