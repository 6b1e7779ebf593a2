// The floating-frame body (ffrf_body) inside scenes (issue 40). Its mass matrix varies with its
// coordinates (the frame's angle and the modal coordinates couple), so the augmented formulation
// re-evaluates and re-factors its block at every state (kit varying_mass.hpp) while the constant
// blocks stay factored once, and its quadratic-velocity forces enter Q. Oracles, on a uniform
// beam of EI = 1 N m^2, rho A = 1 kg/m, L = 1 m:
//  - free-floating with no gravity, spinning and vibrating: its linear and angular momentum and
//    its energy, integrated in the test over the beam's mass from the material points' positions
//    and velocities (not from the body's mass matrix), stay constant to the integrator's tolerance;
//  - released undeformed under gravity it falls as g t^2 / 2 and stays undeformed (the uniform
//    field loads the modes exactly as the frame's acceleration does);
//  - clamped to a hub carried at constant velocity by a driven slider, the first mode vibrates at
//    the Euler-Bernoulli omega_1 = 1.875104068711961^2 sqrt(EI / (rho A L^4)), its period measured
//    from zero crossings of the modal coordinate (a CSV column);
//  - clamped to the ground, `mbd modes` gives the cantilever's four frequencies (beta_i L the roots
//    of cos x cosh x = -1) to 1e-6;
//  - a mode file with a non-positive modal mass, or none at the path given, is refused naming the
//    body and the file:line, exit 2.
#include "support/mass_points.hpp"
#include "support/sampled_run.hpp"
#include "support/test_support.hpp"

#include <mbd/model.hpp>
#include <mbd/simulation.hpp>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace mbd {
namespace {

constexpr double kEI = 1.0, kRhoA = 1.0, kLength = 1.0;  // modulus 1e6 x second_moment 1e-6; density 1 x area 1
constexpr double kBetaL[4] = {1.875104068711961, 4.694091132974175, 7.854757438237613, 10.99554073487547};

double euler_bernoulli(int mode) {
    return kBetaL[mode] * kBetaL[mode] * std::sqrt(kEI / (kRhoA * std::pow(kLength, 4)));
}

std::string blade(int elements, int modes) {
    return "  - {name: blade, type: ffrf_body, from: [0, 0], to: [1, 0], elements: " + std::to_string(elements) +
           ", modes: " + std::to_string(modes) + ", modulus: 1.0e6, area: 1.0, second_moment: 1.0e-6, density: 1.0}\n";
}

// A run's samples: the states and the output rows with their column names.
struct Samples {
    std::vector<State> states;
    test::SampledRun table;
};

Samples run(const Model& model, SimulationSettings settings) {
    settings.diagnostics = true;
    Samples out;
    const SimulationResult result = simulate(model, test::shared_registry(), settings, [&](const SimulationSample& s) {
        out.states.push_back(s.state);
        out.table.rows.push_back(*s.row);
        return true;
    });
    out.table.columns = result.columns;
    return out;
}

// The beam's linear momentum, angular momentum about the world origin and kinetic energy,
// integrated over its mass (rho A dx) by 4-point Gauss-Legendre per element from its material
// points' positions and velocities (FlexibleBody::point), not from its mass matrix. Exact for the
// cubic Hermite modes: r x rdot has degree 6 in x, the rule integrates degree 7.
struct Momenta {
    Eigen::Vector2d linear = Eigen::Vector2d::Zero();
    double angular = 0.0, kinetic = 0.0;
};

Momenta momenta(const FlexibleBodyInstance& f, const State& s, int elements) {
    Momenta out;
    test::for_each_mass_point(f, s, elements, kLength, kRhoA, [&](double dm, const MaterialPoint& p) {
        out.linear += dm * p.rdot.head<2>();
        out.angular += dm * (p.r.x() * p.rdot.y() - p.r.y() * p.rdot.x());
        out.kinetic += 0.5 * dm * p.rdot.head<2>().squaredNorm();
    });
    return out;
}

TEST(FfrfScene, AFreeFloatingBodyKeepsItsMomentaAndItsEnergy) {
    const int elements = 8;
    const Model model = test::scene("dimension: planar\nflexible_bodies:\n" + blade(elements, 4));
    const FlexibleBodyInstance& f = model.flexible_bodies.at(0);
    ASSERT_EQ(f.size, 7);
    // spinning at 1.5 rad/s (below omega_1 = 3.52 rad/s: the linear modes stay bounded), drifting,
    // deformed and vibrating in every mode
    State start = model.initial_state();
    start.q.segment(f.offset + 3, 4) << 0.02, -0.004, 0.001, 0.0005;
    start.v.segment(f.v_offset, 7) << 0.3, -0.2, 1.5, 0.05, -0.03, 0.02, 0.01;
    SimulationSettings settings = test::adaptive_run("augmented", "dopri5", 1e-10, 1.0, 0.05);
    settings.initial_state = start;
    const Samples s = run(model, settings);
    ASSERT_EQ(s.states.size(), 21u);

    const Momenta first = momenta(f, s.states.front(), elements);
    const double energy0 = first.kinetic + f.body->strain_energy(start.q.segment(f.offset, f.size));
    double linear = 0, angular = 0, energy = 0, engine_kinetic = 0;
    for (size_t r = 0; r < s.states.size(); ++r) {
        const Momenta now = momenta(f, s.states[r], elements);
        const double U = f.body->strain_energy(s.states[r].q.segment(f.offset, f.size));
        linear = std::max(linear, (now.linear - first.linear).norm());
        angular = std::max(angular, std::abs(now.angular - first.angular));
        energy = std::max(energy, std::abs(now.kinetic + U - energy0));
        // the engine's 1/2 v^T M(q) v against the integral over the mass
        engine_kinetic = std::max(engine_kinetic, std::abs(s.table.at(r, "kinetic_energy") - now.kinetic));
    }
    std::printf("momenta %.4f %.4f kg m/s, %.4f kg m^2/s, energy %.5f J; largest changes %.2e, %.2e, %.2e; "
                "engine's T against the integral %.2e J\n",
                first.linear.x(), first.linear.y(), first.angular, energy0, linear, angular, energy, engine_kinetic);
    EXPECT_GT(s.table.at(s.states.size() - 1, "blade.angle"), 1.0) << "the frame turned: its mass matrix varied";
    EXPECT_LT(linear, 1e-8 * first.linear.norm());
    EXPECT_LT(angular, 1e-8 * std::abs(first.angular));
    EXPECT_LT(energy, 1e-8 * energy0);
    EXPECT_LT(engine_kinetic, 1e-12 * energy0);
}

TEST(FfrfScene, AnUndeformedBodyFallsAsGTSquaredOverTwo) {
    const Model model = test::scene("dimension: planar\ngravity: [0, -9.81]\nflexible_bodies:\n" + blade(8, 4));
    const test::SampledRun table = test::run_sampled(model, test::adaptive_run("augmented", "dopri5", 1e-10, 1.0, 0.1));
    ASSERT_EQ(table.rows.size(), 11u);
    double fall = 0, drift = 0, deformation = 0;
    for (size_t r = 0; r < table.rows.size(); ++r) {
        const double t = table.at(r, "t");
        fall = std::max(fall, std::abs(table.at(r, "blade.y") + 9.81 * t * t / 2));
        fall = std::max(fall, std::abs(table.at(r, "blade.y_rate") + 9.81 * t));
        fall = std::max(fall, std::abs(table.at(r, "blade.node8.y") + 9.81 * t * t / 2));  // the tip too
        drift = std::max({drift, std::abs(table.at(r, "blade.x")), std::abs(table.at(r, "blade.angle"))});
        for (int i = 1; i <= 4; ++i) deformation = std::max(deformation, std::abs(table.at(r, "blade.mode" + std::to_string(i))));
    }
    // the first cantilever mode is nearly a rigid turn and shift of the frame: M is ill-conditioned,
    // and its solve leaves round-off of about eps cond(M) g in the accelerations
    Eigen::MatrixXd M;
    const FlexibleBodyInstance& f = model.flexible_bodies.at(0);
    f.body->mass_matrix(f.body->initial_coordinates(), M);
    const Eigen::VectorXd eig = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(M).eigenvalues();
    const double cond = eig.maxCoeff() / eig.minCoeff(), round_off = 1e-16 * cond * 9.81;
    std::printf("fall against g t^2 / 2: %.2e m; x and angle %.2e; modes %.2e; cond M %.3g\n", fall, drift, deformation,
                cond);
    EXPECT_NEAR(table.at(10, "blade.y"), -4.905, 1e-9);
    EXPECT_LT(fall, 1e-9);
    EXPECT_LT(drift, 10 * round_off);
    EXPECT_LT(deformation, 10 * round_off);
}

// The first zero crossings of a column, linearly interpolated between samples (a sinusoid has
// no curvature at its zeros: the error is O(omega^2 h^2) of h).
std::vector<double> zero_crossings(const test::SampledRun& table, const std::string& column) {
    std::vector<double> out;
    for (size_t r = 1; r < table.rows.size(); ++r) {
        const double a = table.at(r - 1, column), b = table.at(r, column);
        if ((a < 0) != (b < 0)) {
            const double t0 = table.at(r - 1, "t"), t1 = table.at(r, "t");
            out.push_back(t0 + (t1 - t0) * a / (a - b));
        }
    }
    return out;
}

TEST(FfrfScene, ACantileverOnAMovingHubVibratesAtTheEulerBernoulliFrequency) {
    // the hub slides along y at 0.5 m/s (a driver): the clamp carries the beam's frame with it
    // at constant velocity, which leaves the modal equations pddot + omega_i^2 p = 0
    const std::string text =
        "dimension: planar\nbodies:\n  - {name: hub, mass: 2, inertia: 0.1, position: [0, 0]}\n"
        "flexible_bodies:\n" + blade(20, 4) +
        "joints:\n"
        "  - {name: slide, type: prismatic, bodies: [ground, hub], point: [0, 0], axis: [0, 1]}\n"
        "  - {name: clamp, type: fixed, bodies: [hub, {body: blade, at: 0}], point: [0, 0]}\n"
        "drivers:\n  - {name: carry, joint: slide, motion: {type: linear, initial: 0, rate: 0.5}}\n";
    const Model model = test::scene(text);
    const FlexibleBodyInstance& f = model.flexible_bodies.at(0);
    State start = model.initial_state();
    start.q[f.offset + 3] = 0.01;  // the first mode alone (tip 0.02 m)
    start.v[1] = 0.5, start.v[f.v_offset + 1] = 0.5;
    SimulationSettings settings = test::adaptive_run("augmented", "dopri5", 1e-11, 4.0, 0.005);
    settings.initial_state = start;
    const test::SampledRun table = test::run_sampled(model, settings);
    const std::vector<double> zeros = zero_crossings(table, "blade.mode1");
    ASSERT_GE(zeros.size(), 4u);
    const double period = 2 * (zeros.back() - zeros.front()) / static_cast<double>(zeros.size() - 1);
    const double exact = 2 * std::acos(-1.0) / euler_bernoulli(0);
    std::printf("%zu zero crossings: period %.9f s, Euler-Bernoulli %.9f s, relative %.2e; hub at %.6f m\n",
                zeros.size(), period, exact, period / exact - 1, table.at(table.rows.size() - 1, "hub.y"));
    EXPECT_NEAR(period, exact, 1e-4 * exact);
    EXPECT_NEAR(table.at(table.rows.size() - 1, "blade.y"), 2.0, 1e-8);  // carried along
    EXPECT_NEAR(table.largest("blade.mode1"), 0.01, 1e-6);              // no energy leaves the mode
    EXPECT_LT(table.largest("blade.mode2"), 1e-8);
}

TEST(FfrfScene, TheModesCommandGivesTheCantileversFrequencies) {
    const std::filesystem::path dir = test::scratch("ffrf_modes_cli");
    const std::filesystem::path scene = test::write_text(
        dir / "cantilever.yaml", "dimension: planar\nflexible_bodies:\n" + blade(100, 4) +
                                     "joints:\n  - {name: clamp, type: fixed, bodies: [ground, {body: blade, at: 0}]}\n");
    const std::filesystem::path csv = dir / "modes.csv";
    const test::CommandResult r = test::run_mbd("modes '" + scene.string() + "' --about initial --output '" + csv.string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const test::Csv table = test::read_csv(csv);
    ASSERT_EQ(table.rows.size(), 4u);
    for (int i = 0; i < 4; ++i) {
        const double omega = table.rows[i][table.column("natural_frequency_rad_s")], exact = euler_bernoulli(i);
        std::printf("mode %d: %.10f rad/s, Euler-Bernoulli %.10f, relative %.2e\n", i + 1, omega, exact, omega / exact - 1);
        EXPECT_NEAR(omega, exact, 1e-6 * exact) << "mode " << i + 1;
    }
    EXPECT_GE(table.column("blade.mode1_re"), 0) << "the modes' shapes name the body's coordinates";
}

TEST(FfrfScene, ABadModeFileIsRefusedNamingTheBodyAndTheLine) {
    const std::filesystem::path dir = test::scratch("ffrf_bad_mode_file");
    const std::string scene = "dimension: planar\nflexible_bodies:\n  - {name: plate, type: ffrf_body,\n"
                              "     mode_file: modes.txt}\n";
    test::write_text(dir / "modes.yaml", scene);
    // no file at the path: the scene's key is the line
    test::CommandResult r = test::run_mbd("check '" + (dir / "modes.yaml").string() + "'");
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("body 'plate'"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("modes.yaml:4"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("cannot open the mode file"), std::string::npos) << r.err;
    // a mode whose modal mass is zero: the mode file's line
    test::write_text(dir / "modes.txt", "# two nodes\nnodes 2\n0 0 1\n1 0 1\nmode 0 4.0\n0 0 0\n0 1 1\n");
    r = test::run_mbd("check '" + (dir / "modes.yaml").string() + "'");
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("body 'plate'"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("modes.txt:5"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("modal mass must be positive"), std::string::npos) << r.err;
    // and negative, through a run
    test::write_text(dir / "modes.txt", "nodes 2\n0 0 1\n1 0 1\nmode -2 4.0\n0 0 0\n0 1 1\n");
    r = test::run_mbd("simulate '" + (dir / "modes.yaml").string() + "' --t-end 0.1 --output-step 0.1 --output '" + (dir / "out.csv").string() + "'");
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("body 'plate'"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("modes.txt:4"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "out.csv")) << "no output from a refused scene";
}

}  // namespace
}  // namespace mbd
