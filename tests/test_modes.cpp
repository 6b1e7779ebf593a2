// Linearisation and modes (issue 17) against closed forms: a compound pendulum's
// small-oscillation frequency sqrt(m g l / I), a fixed-fixed chain of three equal masses
// and four equal springs (omega^2 = (k/m)(2 - sqrt 2), 2k/m, (k/m)(2 + sqrt 2)), a damped
// spring-mass's damping ratio c / (2 sqrt(k m)); the input matrix of an actuated pendulum
// (1/I); the refusal of a state that is not an equilibrium.
#include "support/test_support.hpp"

#include <mbd/linearisation.hpp>
#include <mbd/modes.hpp>
#include <mbd/model_system.hpp>
#include <mbd/sdk/text.hpp>
#include <mbd/statics_analysis.hpp>
#include <mbd/simulation.hpp>
#include <mbd/kit/velocity_transform.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace {

using mbd::test::g17;
using mbd::test::scene;

mbd::ModeAnalysis modes_of_scene(const mbd::Model& model, mbd::LinearModel* linear_out = nullptr) {
    mbd::ModelSystem system(model);
    const mbd::LinearModel linear = mbd::linearise(system, model.initial_state(), mbd::scene_actuators(model));
    if (linear_out) *linear_out = linear;
    return mbd::modes_of(linear);
}

struct Pendulum {
    double m = 1.7, J = 0.23, l = 0.8, g = 9.81;
    double I() const { return J + m * l * l; }
    // hanging at rest below the pivot, at angle `angle` from the downward vertical
    std::string yaml(double angle = 0.0, bool actuated = false) const {
        std::ostringstream s;
        s << "dimension: planar\ngravity: [0, " << -g << "]\nbodies:\n"
          << "  - {name: link, mass: " << m << ", inertia: " << J << ", position: [" << g17(l * std::sin(angle))
          << ", " << g17(-l * std::cos(angle)) << "], angle: " << g17(angle) << "}\n"
          << "joints:\n  - {name: pivot, type: revolute, bodies: [ground, link], point: [0, 0]}\n";
        if (actuated) s << "actuators:\n  - {name: motor, joint: pivot}\n";
        return s.str();
    }
};

TEST(Modes, PendulumSmallOscillationFrequency) {
    const Pendulum p;
    mbd::LinearModel linear;
    const mbd::ModeAnalysis a = modes_of_scene(scene(p.yaml()), &linear);
    ASSERT_EQ(linear.coordinates.size(), 1u);
    ASSERT_EQ(a.modes.size(), 1u);
    EXPECT_TRUE(a.modes[0].oscillatory);
    const double omega = std::sqrt(p.m * p.g * p.l / p.I());
    EXPECT_NEAR(a.modes[0].natural_frequency, omega, 1e-10 * omega);
    EXPECT_NEAR(a.modes[0].damping_ratio, 0.0, 1e-10);
    EXPECT_TRUE(a.ignorable.empty());
    // its shape in the joint coordinate: the pivot angle moves one to one with the link's angle
    ASSERT_EQ(a.modes[0].joint_shape.size(), 1);
    EXPECT_NEAR(std::abs(a.modes[0].joint_shape[0]), 1.0, 1e-12);
}

TEST(Modes, ActuatedPendulumInputMatrix) {
    const Pendulum p;
    mbd::LinearModel linear;
    modes_of_scene(scene(p.yaml(0.0, true)), &linear);
    ASSERT_EQ(linear.B.rows(), 2);
    ASSERT_EQ(linear.B.cols(), 1);
    EXPECT_NEAR(linear.B(0, 0), 0.0, 1e-14);
    EXPECT_NEAR(linear.B(1, 0), 1.0 / p.I(), 1e-12 / p.I());  // thetaddot = u / I
    EXPECT_EQ(linear.inputs, std::vector<std::string>{"motor"});
}

TEST(Modes, NotAnEquilibriumGivesTheResidual) {
    const Pendulum p;
    const mbd::Model model = scene(p.yaml(0.5));
    mbd::ModelSystem system(model);
    try {
        mbd::linearise(system, model.initial_state(), {});
        FAIL() << "linearised about a state that is not an equilibrium";
    } catch (const mbd::LinearisationError& e) {
        const std::string what = e.what();
        // thetaddot = -m g l sin(0.5) / I
        const double residual = p.m * p.g * p.l * std::sin(0.5) / p.I();
        EXPECT_NE(what.find("not an equilibrium"), std::string::npos) << what;
        EXPECT_NE(what.find(mbd::format_number(residual)), std::string::npos) << what;
    }
}

// Three blocks on x guides at x = 1, 2, 3 joined by springs to each other and to anchors
// at x = 0 and x = 4 (unstretched, no gravity).
std::string chain_yaml(double m, double k, double c) {
    std::ostringstream s;
    s << "dimension: planar\ngravity: [0, 0]\nbodies:\n";
    for (int i = 1; i <= 3; ++i)
        s << "  - {name: b" << i << ", mass: " << m << ", inertia: 0.01, position: [" << i << ", 0]}\n";
    s << "joints:\n";
    for (int i = 1; i <= 3; ++i)
        s << "  - {name: guide" << i << ", type: prismatic, bodies: [ground, b" << i << "], point: [" << i
          << ", 0], axis: [1, 0]}\n";
    s << "forces:\n";
    const char* names[] = {"ground", "b1", "b2", "b3", "ground"};
    for (int i = 0; i < 4; ++i) {
        s << "  - {name: s" << i << ", type: spring_damper, bodies: [" << names[i] << ", " << names[i + 1]
          << "], points: [[" << (i == 0 ? 0 : 0) << ", 0], [" << (i == 3 ? 4 : 0) << ", 0]], stiffness: " << g17(k)
          << ", damping: " << g17(c) << ", rest_length: 1}\n";
    }
    return s.str();
}

TEST(Modes, ThreeMassChainEigenfrequencies) {
    const double m = 2.0, k = 50.0;
    const mbd::ModeAnalysis a = modes_of_scene(scene(chain_yaml(m, k, 0.0)));
    ASSERT_EQ(a.modes.size(), 3u);
    const double expected[] = {std::sqrt(k / m * (2 - std::sqrt(2.0))), std::sqrt(2 * k / m),
                               std::sqrt(k / m * (2 + std::sqrt(2.0)))};
    for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(a.modes[i].natural_frequency, expected[i], 1e-10 * expected[i]) << i;
        EXPECT_NEAR(a.modes[i].damping_ratio, 0.0, 1e-10) << i;
    }
    // the lowest mode: the blocks move in phase, the middle one sqrt 2 times the outer ones
    const Eigen::VectorXcd& s = a.modes[0].joint_shape;
    ASSERT_EQ(s.size(), 3);
    EXPECT_NEAR(std::abs(s[0] / s[1]), 1.0 / std::sqrt(2.0), 1e-10);
    EXPECT_NEAR(std::abs(s[2] / s[1]), 1.0 / std::sqrt(2.0), 1e-10);
}

TEST(Modes, DampedSpringMassDampingRatio) {
    const double m = 1.3, k = 40.0, c = 1.9;
    // one block between the anchor at x = 0 and a spring without stiffness to x = 2
    std::ostringstream s;
    s << "dimension: planar\ngravity: [0, -9.81]\nbodies:\n  - {name: block, mass: " << m
      << ", inertia: 0.01, position: [1, 0]}\njoints:\n"
      << "  - {name: guide, type: prismatic, bodies: [ground, block], point: [1, 0], axis: [1, 0]}\n"
      << "forces:\n  - {name: spring, type: spring_damper, bodies: [ground, block], points: [[0, 0], [0, 0]], "
      << "stiffness: " << k << ", damping: " << c << ", rest_length: 1}\n";
    const mbd::ModeAnalysis a = modes_of_scene(scene(s.str()));
    ASSERT_EQ(a.modes.size(), 1u);
    const double zeta = c / (2 * std::sqrt(k * m)), omega = std::sqrt(k / m);
    EXPECT_NEAR(a.modes[0].damping_ratio, zeta, 1e-10);
    EXPECT_NEAR(a.modes[0].natural_frequency, omega, 1e-10 * omega);
    EXPECT_NEAR(a.modes[0].damped_frequency, omega * std::sqrt(1 - zeta * zeta), 1e-10 * omega);
}

// A block on a frictionless x guide with no force along it: its position is ignorable.
TEST(Modes, FreeCoordinateIsIgnorable) {
    const mbd::Model model = scene(
        "dimension: planar\ngravity: [0, -9.81]\nbodies:\n  - {name: cart, mass: 2, inertia: 0.1, position: [0, 0]}\n"
        "joints:\n  - {name: rail, type: prismatic, bodies: [ground, cart], point: [0, 0], axis: [1, 0]}\n");
    const mbd::ModeAnalysis a = modes_of_scene(model);
    ASSERT_EQ(a.ignorable.size(), 1u);
    // what is left: the free velocity (lambda = 0, a rigid-body mode)
    ASSERT_EQ(a.modes.size(), 1u);
    EXPECT_NEAR(a.modes[0].natural_frequency, 0.0, 1e-12);
    EXPECT_TRUE(a.modes[0].free_velocity);
}

// A spatial body hanging from a spherical joint: small swings about the body's x and y axes
// at sqrt(m g l / (J + m l^2)) each; the rotation about the vertical is ignorable.
std::string spherical_pendulum_yaml(double m, double Jx, double Jy, double Jz, double l, bool spinning = false) {
    std::ostringstream s;
    s << "dimension: spatial\ngravity: [0, 0, -9.81]\nbodies:\n  - {name: bob, mass: " << m << ", inertia: [" << Jx
      << ", " << Jy << ", " << Jz << "], position: [0, 0, " << -l << "]"
      << (spinning ? ", angular_velocity: [0, 0, 3]" : "") << "}\n"
      << "joints:\n  - {name: O, type: spherical, bodies: [ground, bob], point: [0, 0, 0]}\n";
    return s.str();
}

TEST(Modes, SphericalPendulumSwingsAndIgnorableHeading) {
    const double m = 1.4, Jx = 0.03, Jy = 0.05, Jz = 0.04, l = 0.6, g = 9.81;
    mbd::LinearModel linear;
    const mbd::ModeAnalysis a = modes_of_scene(scene(spherical_pendulum_yaml(m, Jx, Jy, Jz, l)), &linear);
    ASSERT_EQ(linear.coordinates.size(), 3u);
    ASSERT_EQ(a.ignorable.size(), 1u);
    EXPECT_EQ(linear.coordinates[a.ignorable[0].coordinate], "bob.rz");
    EXPECT_TRUE(a.ignorable[0].single);
    // the two swings, and the free rate of the heading (lambda = 0)
    ASSERT_EQ(a.modes.size(), 3u);
    EXPECT_NEAR(a.modes[0].natural_frequency, 0.0, 1e-12);
    const double wy = std::sqrt(m * g * l / (Jy + m * l * l)), wx = std::sqrt(m * g * l / (Jx + m * l * l));
    EXPECT_NEAR(a.modes[1].natural_frequency, wy, 1e-10 * wy);
    EXPECT_NEAR(a.modes[2].natural_frequency, wx, 1e-10 * wx);
}

// A symmetric body (transverse J, axial C about its mass centre) hanging at l below a
// spherical joint and spinning at s about the vertical: tilting by (alpha, beta), the moment of
// momentum about the pivot is A (alphadot, betadot) + C s z_body with A = J + m l^2 and
// z_body = (beta, -alpha, 1), and gravity's moment is -m g l (alpha, beta); with zeta =
// alpha + i beta, A zeta'' - i C s zeta' + m g l zeta = 0, so zeta = e^(i omega t) with
// omega = (C s +- sqrt(C^2 s^2 + 4 A m g l)) / (2 A): two swings, forward and backward.
// The spin angle is ignorable and the spin rate free (a neighbouring steady motion).
TEST(Modes, SpinningHangingTopSwingsAtTheGyroscopicFrequencies) {
    const double m = 1.4, J = 0.03, C = 0.05, l = 0.6, g = 9.81;
    for (double s : {3.0, 30.0}) {
        std::string yaml = spherical_pendulum_yaml(m, J, J, C, l, true);
        yaml = mbd::test::replaced(yaml, "angular_velocity: [0, 0, 3]", "angular_velocity: [0, 0, " + g17(s) + "]");
        const mbd::ModeAnalysis a = modes_of_scene(scene(yaml));
        const double A = J + m * l * l, root = std::sqrt(C * C * s * s + 4 * A * m * g * l);
        const double slow = (root - C * s) / (2 * A), fast = (root + C * s) / (2 * A);
        ASSERT_EQ(a.ignorable.size(), 1u) << "s = " << s;
        ASSERT_EQ(a.modes.size(), 3u) << "s = " << s;
        EXPECT_TRUE(a.modes[0].free_velocity);
        EXPECT_NEAR(a.modes[1].natural_frequency, slow, 1e-9 * slow) << "s = " << s;
        EXPECT_NEAR(a.modes[2].natural_frequency, fast, 1e-9 * fast) << "s = " << s;
        EXPECT_NEAR(a.modes[1].damping_ratio, 0.0, 1e-9);
        EXPECT_NEAR(a.modes[2].damping_ratio, 0.0, 1e-9);
    }
}

// Spinning about an axis its inertia is not symmetric about, the motion does not look the same
// all along it: refused by name.
TEST(Modes, SpinAboutAnUnsymmetricAxisIsRefusedByName) {
    const mbd::Model model = scene(spherical_pendulum_yaml(1.4, 0.03, 0.05, 0.04, 0.6, true));
    mbd::ModelSystem system(model);
    try {
        mbd::linearise(system, model.initial_state(), {});
        FAIL() << "linearised about an unsymmetric spinning body";
    } catch (const mbd::LinearisationError& e) {
        EXPECT_NE(std::string(e.what()).find("body 'bob' turns in the reference state"), std::string::npos) << e.what();
    }
}

// An inverted pendulum held by a torsion spring of exactly k = m g l: the linearised torque
// (k - m g l) theta vanishes, so A's column for the angle is zero, but the nonlinear torque
// m g l (sin theta - theta) is not: the angle is not cyclic, and its double zero eigenvalue is
// reported as modes (the finite-shift check of linearisation.hpp; by A alone it would be
// ignorable). Without gravity and spring the same angle is cyclic.
TEST(Modes, ANeutralButNotCyclicAngleIsReportedAsModes) {
    const double m = 1.3, J = 0.02, l = 0.7, g = 9.81;
    auto yaml = [&](double gravity, double k) {
        return "dimension: planar\ngravity: [0, " + g17(-gravity) + "]\nbodies:\n  - {name: rod, mass: " + g17(m) +
               ", inertia: " + g17(J) + ", position: [0, " + g17(l) + "], angle: 1.5707963267948966}\n" +
               "joints:\n  - {name: pivot, type: revolute, bodies: [ground, rod], point: [0, 0]}\n" +
               "forces:\n  - {name: torsion, type: rotational_spring_damper, bodies: [ground, rod], stiffness: " + g17(k) +
               "}\n";
    };
    mbd::LinearModel linear;
    const mbd::ModeAnalysis neutral = modes_of_scene(scene(yaml(g, m * g * l)), &linear);
    ASSERT_EQ(linear.coordinates.size(), 1u);
    EXPECT_LT(std::abs(linear.A(1, 0)), 1e-9);  // the linear model alone cannot tell
    EXPECT_TRUE(neutral.ignorable.empty());
    int count = 0;
    for (const mbd::Mode& mode : neutral.modes) {
        EXPECT_FALSE(mode.free_velocity);
        EXPECT_LT(mode.natural_frequency, 1e-4);
        count += mode.oscillatory ? 2 : 1;
    }
    EXPECT_EQ(count, 2);
    const mbd::ModeAnalysis free = modes_of_scene(scene(yaml(0.0, 0.0)));
    ASSERT_EQ(free.ignorable.size(), 1u);
    ASSERT_EQ(free.modes.size(), 1u);
    EXPECT_TRUE(free.modes[0].free_velocity);
}

// ---------------------------------------------------------------- upright rolling disc

// A disc (mass m, radius r, axial moment I_a, diametral I_d about its centre G) rolling upright
// without slipping at speed v (spin omega = v / r about its horizontal axle h; heading t = h x Z,
// so that V_G = omega h x r Z = v t), with lean theta (the axle tilted to a = h + theta Z, the
// in-plane up u = Z - theta h, G = C + r u) and heading psi. Linearised Euler equations about G
// (Neimark & Fufaev, Dynamics of Nonholonomic Systems, Ch. II; Greenwood, Advanced Dynamics,
// Sec. 4.7; derived here): H_G = I_a (omega + psi' theta) a + I_d (psi' u + theta' t) to first
// order. Along Z the moment of the contact force F about G, (-r u x F).Z = -r theta F_t, is of
// second order (F_t = m dv/dt = 0 at first order), so H_G.Z = I_d psi' + I_a omega theta is
// constant. Along t: a turns at psi' Z, (da/dt).t = -psi', so (dH_G/dt).t = I_d theta'' -
// I_a omega psi'; the moment is (-r u x F).t = m g r theta + r F_h with F_h = m (v psi' - r theta'')
// (G's lateral acceleration: the heading turning, v psi', and the lean, -r theta''). Hence
//     (I_d + m r^2) theta'' = m g r theta + (I_a + m r^2) omega psi',   I_d psi' = -I_a omega theta + c,
// whose eigenvalues in (theta, theta', psi') are 0 (a steady turn, c != 0) and lambda^2 = mu with
//     mu = (m g r - (I_a + m r^2) I_a omega^2 / I_d) / (I_d + m r^2):
// for a uniform thin disc (I_a = m r^2 / 2, I_d = m r^2 / 4) mu = -4 (3 v^2 - g r) / (5 r^2), stable
// above the known v_c = sqrt(g r / 3). The rest: x, y, heading and spin angle cyclic, the spin
// rate free. Here an unequal I_a, I_d, not a thin disc's, so that the test checks the general form.
struct UprightDisc {
    double m = 2.0, r = 0.3, Ia = 0.07, Id = 0.04, g = 9.81;
    double mu(double v) const {
        const double omega = v / r;
        return (m * g * r - (Ia + m * r * r) * Ia * omega * omega / Id) / (Id + m * r * r);
    }
    double critical_speed() const { return r * std::sqrt(m * g * r * Id / ((Ia + m * r * r) * Ia)); }
    // body z the axle (world y): a rotation by -pi/2 about world x
    std::string yaml(double v) const {
        return "dimension: spatial\ngravity: [0, 0, -" + g17(g) + "]\nbodies:\n  - {name: disc, mass: " + g17(m) +
               ", inertia: [" + g17(Id) + ", " + g17(Id) + ", " + g17(Ia) + "], position: [0, 0, " + g17(r) +
               "], orientation: {axis: [1, 0, 0], angle: " + g17(-M_PI / 2) + "}, velocity: [" + g17(v) +
               ", 0, 0], angular_velocity: [0, " + g17(v / r) + ", 0]}\n"
               "joints:\n  - {name: contact, type: rolling_disc, bodies: [ground, disc], point: [0, 0, " + g17(r) +
               "], axis: [0, 1, 0], radius: " + g17(r) + "}\n";
    }
};

// The lean (disc.rx: the body x axis is the heading) of a position direction of the linear model.
double lean_of(const mbd::LinearModel& linear, const Eigen::VectorXd& direction) {
    return linear.position_map.row(3) * direction;
}

// Every eigenvalue is reported at every speed, the lean pair's through its zero at v_c (|lambda|
// down to 1e-3), and only x, y, heading and spin angle are ignorable. Near v_c the steady turn's
// zero and the lean pair are a near-triple zero (a Jordan block at v_c itself), whose eigenvalues
// move by eps^(1/3) ~ 5e-5 for a perturbation eps ~ 1e-13 of A (the differences' round-off); the
// coefficients of their polynomial lambda (lambda^2 - mu) are not sensitive, and are checked to 1e-9.
TEST(Modes, UprightDiscLeanModeAtEverySpeedAgainstTheEulerEquations) {
    const UprightDisc disc;
    const double vc = disc.critical_speed(), cluster = 5e-5;
    for (double v : {0.0, 0.5, vc - 2e-6, vc - 2e-8, vc + 2e-8, vc + 2e-6, 2.0, 5.0}) {
        mbd::LinearModel linear;
        const mbd::ModeAnalysis a = modes_of_scene(scene(disc.yaml(v)), &linear);
        ASSERT_EQ(linear.coordinates.size(), 5u);
        ASSERT_EQ(linear.velocity_coordinates.size(), 3u);
        // the cyclic ones: four directions, none of them leaning
        ASSERT_EQ(a.ignorable.size(), 4u) << "v = " << v;
        for (const mbd::IgnorableDirection& d : a.ignorable) EXPECT_LT(std::abs(lean_of(linear, d.shape)), 1e-9) << "v = " << v;
        // all 8 eigenvalues: 4 ignorable, the free spin rate, the steady turn and the lean pair
        std::vector<std::complex<double>> lambda;
        int free = 0;
        for (const mbd::Mode& m : a.modes) {
            if (m.free_velocity) {
                ++free;
                continue;
            }
            lambda.push_back(m.eigenvalue);
            if (m.oscillatory) lambda.push_back(std::conj(m.eigenvalue));
        }
        // at rest the heading's rate is free too (no gyroscopic coupling) and there is no steady turn
        EXPECT_EQ(free, v == 0.0 ? 2 : 1) << "v = " << v;
        ASSERT_EQ(lambda.size(), v == 0.0 ? 2u : 3u) << "v = " << v;
        if (v == 0.0) lambda.push_back(0.0);
        std::sort(lambda.begin(), lambda.end(), [](auto x, auto y) { return std::abs(x) < std::abs(y); });
        const double mu = disc.mu(v);
        const std::complex<double> l0 = lambda[0], l1 = lambda[1], l2 = lambda[2];
        const std::complex<double> e1 = l0 + l1 + l2, e2 = l0 * l1 + l0 * l2 + l1 * l2, e3 = l0 * l1 * l2;
        std::printf("v = %.12f: mu = %+.6e, lean pair %+.6e%+.6ei, %+.6e%+.6ei, turn %.1e; e2 + mu = %.1e\n", v, mu,
                    l1.real(), l1.imag(), l2.real(), l2.imag(), std::abs(l0), std::abs(e2 + mu));
        const double tolerance = 1e-9 * std::max(1.0, std::abs(mu));
        EXPECT_LT(std::abs(e1), tolerance) << "v = " << v;
        EXPECT_LT(std::abs(e2 + mu), tolerance) << "v = " << v;
        EXPECT_LT(std::abs(e3), tolerance) << "v = " << v;
        // each eigenvalue: the steady turn at 0, the pair at +-sqrt(mu), real when mu > 0 (falls over)
        EXPECT_LT(std::abs(l0), cluster) << "v = " << v;
        for (const std::complex<double>& l : {l1, l2})
            EXPECT_NEAR(std::abs(l), std::sqrt(std::abs(mu)), 1e-9 * std::sqrt(std::abs(mu)) + cluster) << "v = " << v;
        EXPECT_EQ(std::abs(l1.imag()) > 0.0, mu < 0.0) << "v = " << v;
        EXPECT_EQ(std::abs(l2.imag()) > 0.0, mu < 0.0) << "v = " << v;
        if (std::abs(mu) > 1e-4) EXPECT_LT(std::abs(std::abs(l1) - std::sqrt(std::abs(mu))), 1e-9 * std::sqrt(std::abs(mu)) + 1e-9);
    }
}

// ---------------------------------------------------------------- four-bar with a spring


// scenes/dynamics/four-bar-spring-damper.yaml with its damper removed (a clean frequency)
mbd::Model four_bar_with_spring() {
    std::ifstream in(mbd::test::scene_path("dynamics/four-bar-spring-damper.yaml"));
    std::stringstream text;
    text << in.rdbuf();
    std::string yaml = text.str();
    const size_t at = yaml.find("damping: 10");
    EXPECT_NE(at, std::string::npos);
    yaml.replace(at, 11, "damping: 0");
    return scene(yaml, "four-bar-spring.yaml");
}

mbd::State equilibrium(const mbd::Model& model) {
    const mbd::StaticsReport rep = mbd::run_statics(model, mbd::test::shared_registry(), {});
    EXPECT_TRUE(rep.result.converged) << rep.result.message;
    mbd::State s = rep.result.state;
    s.v = Eigen::VectorXd::Zero(model.nv());
    return s;
}

// The linearised A against first-order central differences (step 1e-6) of the nonlinear
// accelerations of the augmented formulation plugin, on consistent states built around the
// equilibrium along the independent coordinate and its velocity.
TEST(Modes, FourBarLinearisationMatchesDifferencesOfTheNonlinearRhs) {
    const mbd::Model model = four_bar_with_spring();
    mbd::ModelSystem system(model);
    const mbd::LinearModel linear = mbd::linearise(system, equilibrium(model), {});
    ASSERT_EQ(linear.columns.size(), 1u);
    const int col = linear.columns[0];

    mbd::ModelSystem plugin_system(model);
    mbd::FormulationSpec spec{"augmented", "augmented", {}};
    auto formulation = mbd::test::shared_registry().create_formulation(spec, "test");
    formulation->bind(plugin_system, mbd::FormulationOptions{});
    mbd::CoordinatePartition partition;
    {
        mbd::ConstraintValues cv;
        system.constraints(linear.reference, cv, true);
        partition = mbd::partition_coordinates(Eigen::MatrixXd(cv.J));
    }
    ASSERT_EQ(partition.independent, linear.columns);
    auto accel = [&](double dz, double dw) {
        mbd::State s = linear.reference;
        Eigen::VectorXd dv = Eigen::VectorXd::Zero(model.nv());
        dv[col] = dz;
        plugin_system.advance_positions(s.q, dv);
        mbd::ConstraintValues cv;
        Eigen::MatrixXd J;
        mbd::VelocityTransformWorkspace ws;
        EXPECT_TRUE(mbd::correct_dependent_positions(plugin_system, s, partition, 1e-14, 30, cv, J, ws));
        mbd::dependent_velocities(J, cv.C_t, partition, Eigen::VectorXd::Constant(1, dw), s.v, ws);
        Eigen::VectorXd vdot;
        formulation->accelerations(s, vdot);
        return vdot[col];
    };
    const double h = 1e-6;
    const double dadz = (accel(h, 0) - accel(-h, 0)) / (2 * h), dadw = (accel(0, h) - accel(0, -h)) / (2 * h);
    const double scale = linear.A.cwiseAbs().maxCoeff();
    EXPECT_NEAR(linear.A(1, 0), dadz, 1e-6 * scale);
    EXPECT_NEAR(linear.A(1, 1), dadw, 1e-6 * scale);
    EXPECT_EQ(linear.A(0, 0), 0.0);
    EXPECT_EQ(linear.A(0, 1), 1.0);
}

// The natural frequency against the period of a small-amplitude free oscillation simulated
// from the equilibrium (rocker angle zero crossings, interpolated, over ten periods).
TEST(Modes, FourBarFrequencyMatchesASmallAmplitudeSimulation) {
    const mbd::Model model = four_bar_with_spring();
    mbd::ModelSystem system(model);
    const mbd::LinearModel linear = mbd::linearise(system, equilibrium(model), {});
    const mbd::ModeAnalysis a = mbd::modes_of(linear);
    ASSERT_EQ(a.modes.size(), 1u);
    const double omega = a.modes[0].natural_frequency;
    ASSERT_GT(omega, 0.0);

    mbd::SimulationSettings settings;
    settings.formulation = "augmented";
    settings.integration.tolerance = 1e-12;
    settings.t_end = 10.5 * 2 * M_PI / omega;
    settings.output_step = 1e-4;
    settings.progress = false;
    settings.messages = mbd::MessageLog::silent();
    mbd::State start = linear.reference;
    start.v = linear.velocity_map * Eigen::VectorXd::Constant(1, 1e-4 * omega);  // amplitude 1e-4 rad
    settings.initial_state = start;
    const int col = linear.columns[0];
    const double rest = linear.reference.q[col];  // planar: the angle column is its coordinate
    std::vector<double> crossings;
    double last_t = 0.0, last_x = 0.0;
    bool first = true;
    mbd::simulate(model, mbd::test::shared_registry(), settings, [&](const mbd::SimulationSample& s) {
        const double x = s.state.q[col] - rest;
        if (!first && ((last_x < 0) != (x < 0)) && x != last_x)
            crossings.push_back(last_t + (s.state.t - last_t) * last_x / (last_x - x));
        first = false;
        last_t = s.state.t, last_x = x;
        return true;
    });
    ASSERT_GE(crossings.size(), 21u);
    const double period = 2 * (crossings[20] - crossings[0]) / 20;
    EXPECT_NEAR(2 * M_PI / period, omega, 1e-4 * omega);
}

// ---------------------------------------------------------------- the command

struct ModesCli : ::testing::Test {
    // one folder per test: ctest runs the tests of this fixture in parallel processes
    std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                (std::string("mbd_modes_cli_") +
                                 ::testing::UnitTest::GetInstance()->current_test_info()->name());
    void SetUp() override {
        std::filesystem::remove_all(dir);
        std::filesystem::create_directories(dir);
    }
    std::string write(const std::string& name, const std::string& text) {
        std::ofstream(dir / name) << text;
        return (dir / name).string();
    }
};

TEST_F(ModesCli, WritesTheModesAndTheStateSpace) {
    const Pendulum p;
    // drawn away from the equilibrium: --about statics finds it first
    const std::string file = write("pendulum.yaml", p.yaml(0.7, true));
    const std::string csv = (dir / "modes.csv").string(), ab = (dir / "ab.csv").string();
    const mbd::test::CommandResult r =
        mbd::test::run_mbd("modes '" + file + "' --output '" + csv + "' --state-space '" + ab + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const mbd::test::Csv modes = mbd::test::read_csv(csv);
    ASSERT_EQ(modes.rows.size(), 1u);
    const double omega = std::sqrt(p.m * p.g * p.l / p.I());
    EXPECT_NEAR(modes.rows[0][modes.column("natural_frequency_rad_s")], omega, 1e-8 * omega);
    EXPECT_NEAR(modes.rows[0][modes.column("natural_frequency_hz")], omega / (2 * M_PI), 1e-8 * omega);
    const mbd::test::Csv state_space = mbd::test::read_csv(ab);
    ASSERT_EQ(state_space.rows.size(), 2u);
    EXPECT_NEAR(state_space.rows[1][state_space.column("B.motor")], 1.0 / p.I(), 1e-10 / p.I());
    EXPECT_NEAR(state_space.rows[1][state_space.column("A.link.angle")], -omega * omega, 1e-7 * omega * omega);
}

TEST_F(ModesCli, NotAnEquilibriumIsRefusedWithItsResidualAndNoFile) {
    const Pendulum p;
    const std::string file = write("pendulum.yaml", p.yaml(0.5));
    const std::string csv = (dir / "modes.csv").string();
    const mbd::test::CommandResult r = mbd::test::run_mbd("modes '" + file + "' --about initial --output '" + csv + "'");
    EXPECT_NE(r.exit_code, 0);
    const double residual = p.m * p.g * p.l * std::sin(0.5) / p.I();
    EXPECT_NE(r.err.find("not an equilibrium or steady motion"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(mbd::format_number(residual)), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(csv));
    EXPECT_FALSE(std::filesystem::exists(csv + ".partial"));
}

TEST_F(ModesCli, FailedStaticsWritesNoModes) {
    const Pendulum p;
    const std::string file = write("pendulum.yaml", p.yaml(0.5));
    const std::string csv = (dir / "modes.csv").string();
    const mbd::test::CommandResult r =
        mbd::test::run_mbd("modes '" + file + "' --statics-iterations 1 --output '" + csv + "'");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find("did not converge"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(csv));
    EXPECT_FALSE(std::filesystem::exists(csv + ".partial"));
}

TEST_F(ModesCli, JsonHasTheModesAndMatrices) {
    const std::string file = write("chain.yaml", chain_yaml(2.0, 50.0, 0.5));
    const mbd::test::CommandResult r = mbd::test::run_mbd("modes '" + file + "' --about initial --json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j["modes"].size(), 3u);
    EXPECT_EQ(j["A"].size(), 6u);
    EXPECT_EQ(j["coordinates"].size(), 3u);
    // the lowest mode of the damped chain: omega_n^2 = (k/m)(2 - sqrt 2), 2 zeta omega_n = (c/m)(2 - sqrt 2)
    const double k_m = 25.0, c_m = 0.25, w2 = k_m * (2 - std::sqrt(2.0));
    EXPECT_NEAR(j["modes"][0]["natural_frequency"].get<double>(), std::sqrt(w2), 1e-9);
    EXPECT_NEAR(j["modes"][0]["damping_ratio"].get<double>(), c_m * (2 - std::sqrt(2.0)) / (2 * std::sqrt(w2)), 1e-9);
}

// The four-bar of scenes/four-bar.yaml: its motor drives the only freedom. Refused with the
// cause named (issue 42: it said to try --about statics, the default), and what to do.
TEST_F(ModesCli, FullyDrivenMechanismNamesItsDriver) {
    const std::string csv = (dir / "modes.csv").string();
    const std::string four_bar = mbd::test::scene_path("four-bar.yaml").string();
    for (const char* about : {"statics", "initial"}) {
        const mbd::test::CommandResult r =
            mbd::test::run_mbd("modes '" + four_bar + "' --about " + about + " --output '" + csv + "'");
        EXPECT_EQ(r.exit_code, 1) << about;
        EXPECT_NE(r.err.find(four_bar + ": no freedom to linearise"), std::string::npos) << r.err;  // the file named
        EXPECT_NE(r.err.find("the driver 'motor' (joint 'O') prescribes"), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("remove the driver"), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("actuator"), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("run `mbd kinematics`"), std::string::npos) << r.err;  // the driven motion's own command
        EXPECT_EQ(r.err.find("--about statics"), std::string::npos) << r.err;
        EXPECT_FALSE(std::filesystem::exists(csv));
    }
    // the same four-bar with the driver made an actuator has its one mode
    std::string yaml = mbd::test::read_text(four_bar);
    const size_t at = yaml.find("drivers:");
    ASSERT_NE(at, std::string::npos);
    yaml = yaml.substr(0, at) + "actuators:\n  - {name: motor, joint: O}\n";
    const mbd::test::CommandResult r = mbd::test::run_mbd("modes '" + write("four-bar.yaml", yaml) + "' --json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["modes"].size(), 1u);
}

// A body held by a fixed joint: no freedom and no driver; said so, not an empty table.
TEST_F(ModesCli, MechanismWithoutFreedomSaysSo) {
    const std::string file = write("fixed.yaml",
                                   "dimension: planar\ngravity: [0, -9.81]\nbodies:\n  - {name: block, mass: 1, inertia: "
                                   "0.1, position: [0, 0]}\njoints:\n  - {name: weld, type: fixed, bodies: [ground, "
                                   "block], point: [0, 0]}\n");
    const mbd::test::CommandResult r = mbd::test::run_mbd("modes '" + file + "' --about initial");
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.err.find("no freedom to linearise: the joints fix every body"), std::string::npos) << r.err;
    EXPECT_EQ(r.out.find("mode "), std::string::npos) << r.out;
}

}  // namespace
