// Friction whose normal load is a joint's own reaction (issue 19, item 3: `load_joint` of the
// coulomb_friction and rotational_friction elements, kit reaction_loads.hpp), and the energy
// friction dissipates (the diagnostics column friction_dissipated), against closed forms:
//  - a block on a prismatic guide inclined at `angle`: the guide's normal reaction is
//    m g cos(angle) whatever the friction along it, so the block sticks when
//    tan(angle) <= mu_s and otherwise slides with a = g (sin - mu_k cos);
//  - a wheel on a pin under its weight and a torque: breakaway at mu_s r m g + M_p;
//  - a pendulum whose pin friction changes the pin reaction that loads it (the loop), below;
//  - the energy balance E(0) - E(t) = friction_dissipated(t), and the dissipated energy
//    against mu_k N times the distance slid (Ex. 5.6 and the incline).
#include "support/test_support.hpp"

#include <mbd/linearisation.hpp>
#include <mbd/model_system.hpp>
#include <mbd/kit/formulation.hpp>
#include <mbd/simulation.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

using mbd::test::g17;

constexpr double kG = 9.81;

struct Motion {
    std::vector<mbd::State> states;
    std::vector<double> dissipated;  // the column friction_dissipated, per sample
    std::vector<double> energy;      // kinetic + potential, per sample
};

Motion run(const mbd::Model& model, double t_end, double output_step, double tolerance,
        const std::string& formulation = "augmented") {
    mbd::SimulationSettings s;
    s.formulation = formulation;
    s.integrator = "cvode";
    s.integration.tolerance = tolerance;
    s.t_end = t_end;
    s.output_step = output_step;
    s.progress = false;
    s.diagnostics = true;
    s.messages = mbd::MessageLog::silent();
    Motion out;
    std::vector<std::string> columns;
    const mbd::SimulationResult result = mbd::simulate(model, mbd::test::shared_registry(), s, [&](const mbd::SimulationSample& sample) {
        out.states.push_back(sample.state);
        const std::vector<double>& row = *sample.row;
        out.dissipated.push_back(row.back());  // the last column
        out.energy.push_back(row[row.size() - 5] + row[row.size() - 4]);  // kinetic, potential, 2 violations, E_f
        return true;
    });
    EXPECT_EQ(result.columns.back(), mbd::kFrictionDissipatedColumn);
    EXPECT_EQ(result.columns[result.columns.size() - 5], "kinetic_energy");
    return out;
}

// ------------------------------------------------------------------ a guide on an incline
// A 2 kg block on a prismatic guide at `angle`, gravity down; the friction element's load is the
// guide's normal reaction (load_joint: slope), not a given number.
std::string incline_scene(double angle, double mu_s, double mu_k) {
    const double c = std::cos(angle), s = std::sin(angle);
    const std::string axis = "[" + g17(c) + ", " + g17(s) + "]";
    return "name: guide-incline\ndimension: planar\ngravity: [0, " + g17(-kG) + "]\n"
           "bodies:\n  - {name: block, mass: 2, inertia: 0.01, position: [0, 0], angle: " + g17(angle) + "}\n"
           "joints:\n  - {name: slope, type: prismatic, bodies: [ground, block], point: [0, 0], axis: " + axis + "}\n"
           "forces:\n"
           "  - {name: dry, type: coulomb_friction, bodies: [block, ground], point: [0, 0], axis: " + axis +
           ", load_joint: slope, static_friction: " + g17(mu_s) + ", kinetic_friction: " + g17(mu_k) +
           ", stiction_velocity: 1e-9}\n";
}
double along(const mbd::State& st, double angle) { return st.q[0] * std::cos(angle) + st.q[1] * std::sin(angle); }
double speed_along(const mbd::State& st, double angle) { return st.v[0] * std::cos(angle) + st.v[1] * std::sin(angle); }

TEST(JointFriction, GuideOnAnInclineSticksUpToTheStaticCoefficient) {
    const double mu_s = 0.4, mu_k = 0.3;
    for (double tan_angle : {0.2, 0.39, mu_s}) {
        const double angle = std::atan(tan_angle);
        const Motion r = run(mbd::test::scene(incline_scene(angle, mu_s, mu_k)), 1.0, 0.05, 1e-12);
        double travel = 0.0;
        for (const auto& st : r.states) travel = std::max(travel, std::abs(along(st, angle)));
        std::printf("guide on incline, tan %.3f (mu_s %.2f): travel in 1 s %.3e m\n", tan_angle, mu_s, travel);
        // within the stiction velocity times 1 s (twice that at tan = mu_s: the plateau of the law)
        EXPECT_LT(travel, (tan_angle < mu_s ? 1.0 : 2.0) * 1e-9 + 1e-12) << "tan(angle) = " << tan_angle;
    }
}

TEST(JointFriction, GuideOnAnInclineSlidesWithTheKineticCoefficientAndItsNormalReaction) {
    const double mu_s = 0.4, mu_k = 0.3, m = 2.0;
    for (double tan_angle : {mu_s * 1.001, 0.7, 2.0}) {
        const double angle = std::atan(tan_angle);
        const mbd::Model model = mbd::test::scene(incline_scene(angle, mu_s, mu_k));
        const Motion r = run(model, 1.0, 0.05, 1e-12);
        const double a = kG * (std::sin(angle) - mu_k * std::cos(angle));
        const mbd::State &s1 = r.states[10], &s2 = r.states.back();
        const double measured = (speed_along(s1, angle) - speed_along(s2, angle)) / (s2.t - s1.t);  // down the slope
        std::printf("guide on incline, tan %.4f: a %.12f, closed form %.12f, error %.2e\n", tan_angle, measured, a,
                    measured - a);
        EXPECT_NEAR(measured, a, 1e-8) << "tan(angle) = " << tan_angle;
        // the load the formulation solved: the normal reaction m g cos(angle)
        mbd::ModelSystem system(model);
        mbd::Param node;
        auto augmented = mbd::test::make_formulation("augmented", node);
        augmented->bind(system, {});
        Eigen::VectorXd vdot;
        augmented->accelerations(s2, vdot);
        ASSERT_EQ(system.reaction_loads().size(), 1);
        EXPECT_NEAR(system.reaction_loads()[0], m * kG * std::cos(angle), 1e-11);
        // the energy it dissipated: the balance, and mu_k N times the distance slid
        const double slid = -along(s2, angle);  // down the slope from 0
        const double closed = mu_k * m * kG * std::cos(angle) * slid;
        const double balance = r.energy.front() - r.energy.back();
        std::printf("  dissipated %.12f J, E0 - E %.12f J, mu_k N x distance %.12f J\n", r.dissipated.back(), balance,
                    closed);
        EXPECT_NEAR(r.dissipated.back(), balance, 1e-9 * (1.0 + balance));
        EXPECT_NEAR(r.dissipated.back(), closed, 1e-8 * (1.0 + closed));
    }
}

// ------------------------------------------------------------------ a pin under its weight
// A wheel (m = 2 kg, J = 0.5 kg m^2) on a pin, gravity down, so the pin's reaction is m g =
// 19.62 N; pin radius 0.05 m, mu_s 0.3, mu_k 0.2, preload 0.5 N m: breakaway
// M_s = 0.3 * 0.05 * 19.62 + 0.5 = 0.7943 N m, slipping M_k = 0.2 * 0.05 * 19.62 + 0.5 = 0.6962 N m.
std::string pin_scene(double torque) {
    return "name: pin\ndimension: planar\ngravity: [0, " + g17(-kG) + "]\n"
           "bodies:\n  - {name: wheel, mass: 2, inertia: 0.5, position: [0, 0]}\n"
           "  - {name: hub, mass: 1, inertia: 0.1, position: [1, 0]}\n"
           "joints:\n  - {name: hub-pin, type: revolute, bodies: [ground, hub], point: [1, 0]}\n"
           "  - {name: axle, type: revolute, bodies: [ground, wheel], point: [0, 0]}\n"
           "forces:\n"
           "  - {name: motor, type: point_torque, body: wheel, torque: " + g17(torque) + "}\n"
           "  - {name: bearing, type: rotational_friction, bodies: [wheel, ground], point: [0, 0], radius: 0.05,"
           " load_joint: axle, static_friction: 0.3, kinetic_friction: 0.2, preload: 0.5, stiction_velocity: 1e-9}\n";
}

TEST(JointFriction, PinLoadedByItsReactionHoldsBelowBreakawayAndSlipsAbove) {
    const double N = 2.0 * kG, breakaway = 0.3 * 0.05 * N + 0.5, kinetic = 0.2 * 0.05 * N + 0.5;
    for (double torque : {0.3, 0.79, breakaway, -0.79}) {
        double turned = 0.0;
        for (const auto& st : run(mbd::test::scene(pin_scene(torque)), 1.0, 0.05, 1e-12).states)
            turned = std::max(turned, std::abs(st.q[2]));
        std::printf("pin loaded by its reaction, torque %.4f N m (breakaway %.4f): turned %.3e rad in 1 s\n", torque,
                    breakaway, turned);
        EXPECT_LT(turned, (std::abs(torque) < breakaway ? 1.0 : 2.0) * 1e-9 + 1e-12) << torque;
    }
    for (double torque : {0.8, 2.0, -3.0}) {
        const Motion r = run(mbd::test::scene(pin_scene(torque)), 1.0, 0.05, 1e-12);
        const mbd::State &a = r.states[4], &b = r.states.back();
        const double measured = (b.v[2] - a.v[2]) / (b.t - a.t);
        const double exact = (torque - (torque > 0 ? kinetic : -kinetic)) / 0.5;
        std::printf("pin loaded by its reaction, torque %.2f: %.12f rad/s^2, closed form %.12f\n", torque, measured, exact);
        EXPECT_NEAR(measured, exact, 1e-8) << torque;
    }
}

// ------------------------------------------------------------------ a spatial hinge
// The spatial path: a flywheel (m = 3 kg, J = diag(0.3, 0.3, 0.5) kg m^2, body z along the
// hinge) on a revolute whose axis a is tilted by 0.5 rad from the vertical, its mass centre on
// the axis. Turning at a constant rate or at rest, a_G = 0, so the hinge's reaction is -m g and
// its part transverse to a, the load, is N = m g sin(0.5) (the axial part is not). Pin radius
// 0.02 m, mu_s 0.3, mu_k 0.2, preload 0.5 N m: breakaway M_s = 0.3 * 0.02 N + 0.5, slipping
// M_k = 0.2 * 0.02 N + 0.5; a motor torque T about a: held below M_s, else J_zz w' = T - M_k.
std::string spatial_hinge_scene(double torque) {
    const std::string axis = "[0, " + g17(-std::sin(0.5)) + ", " + g17(std::cos(0.5)) + "]";
    return "name: spatial-hinge\ndimension: spatial\ngravity: [0, 0, " + g17(-kG) + "]\n"
           "bodies:\n  - {name: flywheel, mass: 3, inertia: [0.3, 0.3, 0.5], position: [0, 0, 0],"
           " orientation: {axis: [1, 0, 0], angle: 0.5}}\n"
           "joints:\n  - {name: hinge, type: revolute, bodies: [ground, flywheel], point: [0, 0, 0], axis: " + axis + "}\n"
           "forces:\n"
           "  - {name: motor, type: point_torque, body: flywheel, torque: [0, 0, " + g17(torque) + "], frame: body}\n"
           "  - {name: bearing, type: rotational_friction, bodies: [flywheel, ground], point: [0, 0, 0], axis: " + axis +
           ", radius: 0.02, load_joint: hinge, static_friction: 0.3, kinetic_friction: 0.2, preload: 0.5,"
           " stiction_velocity: 1e-9}\n";
}

TEST(JointFriction, SpatialHingeLoadedByItsTransverseReaction) {
    const double N = 3.0 * kG * std::sin(0.5), breakaway = 0.3 * 0.02 * N + 0.5, kinetic = 0.2 * 0.02 * N + 0.5;
    for (double torque : {0.3, 0.99 * breakaway, -0.99 * breakaway}) {
        const mbd::Model model = mbd::test::scene(spatial_hinge_scene(torque));
        const Motion r = run(model, 1.0, 0.05, 1e-12);
        double turned = 0.0;  // |w| integrated: at most the stiction rate times 1 s
        for (const auto& st : r.states) turned = std::max(turned, st.v.tail<3>().norm());
        std::printf("spatial hinge, torque %.4f N m (breakaway %.4f): largest rate %.3e rad/s\n", torque, breakaway,
                    turned);
        EXPECT_LT(turned, 1e-9) << torque;
        // the load the formulation solved: the transverse reaction, the axial part left out
        mbd::ModelSystem system(model);
        mbd::Param node;
        auto augmented = mbd::test::make_formulation("augmented", node);
        augmented->bind(system, {});
        Eigen::VectorXd vdot;
        augmented->accelerations(r.states.back(), vdot);
        ASSERT_EQ(system.reaction_loads().size(), 1);
        EXPECT_NEAR(system.reaction_loads()[0], N, 1e-11 * N) << torque;
    }
    for (double torque : {2.0, -3.0}) {
        const Motion r = run(mbd::test::scene(spatial_hinge_scene(torque)), 1.0, 0.05, 1e-12);
        const mbd::State &a = r.states[4], &b = r.states.back();
        const double measured = (b.v[5] - a.v[5]) / (b.t - a.t);  // body z: along the hinge
        const double exact = (torque - (torque > 0 ? kinetic : -kinetic)) / 0.5;
        std::printf("spatial hinge, torque %.2f: %.12f rad/s^2, closed form %.12f\n", torque, measured, exact);
        EXPECT_NEAR(measured, exact, 1e-8) << torque;
        EXPECT_LT(b.v.head<3>().norm() + b.v.segment<2>(3).norm(), 1e-9) << torque;  // only the turn about a
    }
}

// ------------------------------------------------------------------ the loop: a pendulum
// A bar (m = 3 kg, centroidal J_c = 0.05 kg m^2) pinned to the ground at O = (0, 0), its mass
// centre at (l, 0) = (0.4, 0), turning at w = 5 rad/s (counter-clockwise, slipping: mu = mu_k),
// gravity (0, -g). Pin friction: radius r = 0.05 m, mu_k = 0.3, preload M_p = 0.1 N m, loaded by
// the pin's reaction F, which depends on the angular acceleration A that the friction changes:
//   a_G = (-w^2 l, A l),  F = m a_G - m g_vec = m (-w^2 l, A l + g),
//   J_O A = -m g l - (mu_k r |F| + M_p),  J_O = J_c + m l^2,
// so with c = m g l + M_p and k = mu_k r m:  (J_O A + c)^2 = k^2 (w^4 l^2 + (A l + g)^2), the
// root with J_O A + c < 0 of
//   (J_O^2 - k^2 l^2) A^2 + 2 (J_O c - k^2 l g) A + c^2 - k^2 (w^4 l^2 + g^2) = 0.
struct Pendulum {
    double m = 3.0, Jc = 0.05, l = 0.4, w = 5.0, r = 0.05, mu_k = 0.3, mu_s = 0.4, preload = 0.1;
    double JO() const { return Jc + m * l * l; }
    double closed_form() const {
        const double c = m * kG * l + preload, k = mu_k * r * m;
        const double a2 = JO() * JO() - k * k * l * l, a1 = 2.0 * (JO() * c - k * k * l * kG),
                     a0 = c * c - k * k * (std::pow(w, 4) * l * l + kG * kG);
        const double root = std::sqrt(a1 * a1 - 4.0 * a2 * a0);
        const double A1 = (-a1 + root) / (2.0 * a2), A2 = (-a1 - root) / (2.0 * a2);
        return JO() * A1 + c < 0.0 ? A1 : A2;
    }
    // the same with the load lagged: |F| of the frictionless acceleration (what a step-lagged
    // load would use), to show that the loop matters here
    double lagged() const {
        const double A0 = -(m * kG * l + preload) / JO();
        const double F = m * std::hypot(w * w * l, A0 * l + kG);
        return -(m * kG * l + mu_k * r * F + preload) / JO();
    }
    std::string yaml(double stiction_velocity) const {
        return "name: friction-pendulum\ndimension: planar\ngravity: [0, " + g17(-kG) + "]\n"
               "bodies:\n  - {name: bar, mass: " + g17(m) + ", inertia: " + g17(Jc) + ", position: [" + g17(l) +
               ", 0], velocity: [0, " + g17(w * l) + "], angular_velocity: " + g17(w) + "}\n"
               "joints:\n  - {name: pivot, type: revolute, bodies: [ground, bar], point: [0, 0]}\n"
               "forces:\n"
               "  - {name: pin, type: rotational_friction, bodies: [bar, ground], point: [0, 0], radius: " + g17(r) +
               ", load_joint: pivot, static_friction: " + g17(mu_s) + ", kinetic_friction: " + g17(mu_k) +
               ", preload: " + g17(preload) + ", stiction_velocity: " + g17(stiction_velocity) + "}\n";
    }
};

TEST(JointFriction, PendulumPinFrictionSolvesTheLoopWithItsReaction) {
    const Pendulum p;
    const mbd::Model model = mbd::test::scene(p.yaml(1e-6));
    mbd::ModelSystem system(model);
    mbd::Param node;
    auto augmented = mbd::test::make_formulation("augmented", node);
    augmented->bind(system, {});
    mbd::State s = system.initial_state();
    s.t = 0.0;
    Eigen::VectorXd vdot, lambda;
    augmented->accelerations(s, vdot);
    const double exact = p.closed_form();
    std::printf("friction pendulum: A %.15f rad/s^2, closed form %.15f, lagged load %.15f\n", vdot[2], exact, p.lagged());
    EXPECT_NEAR(vdot[2], exact, 1e-12 * std::abs(exact));
    EXPECT_GT(std::abs(p.lagged() - exact), 1e-4);  // the loop changes the answer far beyond the tolerance
    // the load is the magnitude of the pin reaction the multipliers give
    augmented->multipliers(s, lambda);
    const double F = p.m * std::hypot(p.w * p.w * p.l, exact * p.l + kG);
    EXPECT_NEAR(system.reaction_loads()[0], F, 1e-11 * F);
    EXPECT_NEAR(vdot[0], -p.w * p.w * p.l, 1e-12);  // a_G = (-w^2 l, A l)
    EXPECT_NEAR(vdot[1], exact * p.l, 1e-12);
}

TEST(JointFriction, PendulumComesToRestWithItsEnergyDissipatedByThePin) {
    const Pendulum p;
    const Motion r = run(mbd::test::scene(p.yaml(1e-6)), 6.0, 0.01, 1e-11);
    double worst = 0.0;
    for (size_t k = 0; k < r.states.size(); ++k)
        worst = std::max(worst, std::abs(r.energy.front() - r.energy[k] - r.dissipated[k]));
    std::printf("friction pendulum: E0 %.9f J, dissipated %.9f J, worst |E0 - E - dissipated| %.3e J\n",
                r.energy.front(), r.dissipated.back(), worst);
    EXPECT_LT(worst, 1e-7);
    for (size_t k = 1; k < r.dissipated.size(); ++k) EXPECT_GE(r.dissipated[k], r.dissipated[k - 1] - 1e-12);
    EXPECT_GT(r.dissipated.back(), 0.5 * r.energy.front() - 0.5 * r.energy.back());
}

// ------------------------------------------------------------------ a stuck pin's creep
// scenes/extreme/pin-friction-holds.yaml: a 2 kg link on a pin whose friction holds it against
// gravity, creeping within the stiction band (a stiff relaxation, rate ~1e8 1/s). cvode at
// 1e-10 with the dissipation column used to fail its error test at t = 0.024 (the column's
// own test; it is a quadrature left out of cvode's error control now): the run reaches 2 s,
// and the column equals the energy the link lost, E(0) - E(t) (no driver, no other
// non-conservative force), at every sample.
TEST(JointFriction, StuckPinCreepDissipationByCvodeAtTightTolerance) {
    const Motion r = run(mbd::test::load("extreme/pin-friction-holds.yaml"), 2.0, 0.01, 1e-10);
    ASSERT_EQ(r.states.size(), 201u);
    double worst = 0.0;
    for (size_t k = 0; k < r.states.size(); ++k)
        worst = std::max(worst, std::abs(r.energy.front() - r.energy[k] - r.dissipated[k]));
    const double lost = r.energy.front() - r.energy.back();
    std::printf("stuck pin: E0 - E(2 s) %.6e J, dissipated %.6e J, worst |E0 - E - dissipated| %.2e J\n", lost,
                r.dissipated.back(), worst);
    EXPECT_GT(lost, 0.0);  // it creeps: the balance is not 0 = 0
    EXPECT_LT(worst, 1e-9 * lost);  // measured 2.5e-16 J of 1.5e-6 J
}

// ------------------------------------------------------------------ Ex. 5.6's energy
// The digest's oscillator (tests/test_friction.cpp): 5 kg, k = 5e3 N/m, mu_k = 0.1, x0 = 0.03 m,
// 15 half cycles; F_f = mu m g slides the distance sum_n (A_n + A_(n+1)).
TEST(JointFriction, BookExample5_6DissipatedEnergyColumn) {
    const double m = 5.0, k = 5e3, mu = 0.1, x0 = 0.03, Ff = mu * m * kG, drop = 2.0 * Ff / k;
    const std::string yaml =
        "name: ex5-6\ndimension: planar\n"
        "bodies:\n  - {name: block, mass: 5, inertia: 0.01, position: [0.03, 0]}\n"
        "joints:\n  - {name: guide, type: prismatic, bodies: [ground, block], point: [0, 0], axis: [1, 0]}\n"
        "forces:\n"
        "  - {name: spring, type: spring_damper, bodies: [ground, block], points: [[-1, 0], [0, 0]], stiffness: 5000,"
        " rest_length: 1}\n"
        "  - {name: dry, type: coulomb_friction, bodies: [block, ground], point: [0.03, 0], axis: [1, 0], normal_force: " +
        g17(m * kG) + ", static_friction: 0.1, kinetic_friction: 0.1, stiction_velocity: 1e-9}\n";
    const double t_half = 3.14159265358979323846 / std::sqrt(k / m);
    const Motion r = run(mbd::test::scene(yaml), 15 * t_half + 1.2, t_half / 40, 1e-12);
    double path = 0.0;
    for (int n = 0; n < 15; ++n) path += 2.0 * (x0 - n * drop) - drop;
    double worst = 0.0;
    for (size_t s = 0; s < r.states.size(); ++s)
        worst = std::max(worst, std::abs(r.energy.front() - r.energy[s] - r.dissipated[s]));
    std::printf("Ex. 5.6: friction_dissipated %.10f J, F_f x path %.10f J, worst |E0 - E - dissipated| %.3e J\n",
                r.dissipated.back(), Ff * path, worst);
    // 2.25 J dissipated; the balance holds to the integration error of the spring's energy
    // (cvode at 1e-12 over 15 half cycles: measured 1.0e-8 J)
    EXPECT_NEAR(r.dissipated.back(), Ff * path, 1e-7);
    EXPECT_LT(worst, 5e-8);
    // after the half cycle ending at rest: F_f times the distance slid so far, at each turning point
    for (int n = 1; n <= 15; ++n) {
        double slid = 0.0;
        for (int h = 0; h < n; ++h) slid += 2.0 * (x0 - h * drop) - drop;
        EXPECT_NEAR(r.dissipated[n * 40], Ff * slid, 1e-7) << n;
    }
}

// ------------------------------------------------------------------ refusals and bad input
std::string error_of(const std::string& yaml, const std::string& formulation = "augmented",
                     const std::string& integrator = "cvode") {
    try {
        const mbd::Model model = mbd::test::scene(yaml, "joint-friction.yaml");
        mbd::SimulationSettings s;
        s.formulation = formulation;
        s.integrator = integrator;
        s.integration.step = integrator == "generalized_alpha" ? 1e-3 : 0.0;
        s.t_end = 0.01;
        s.output_step = 0.005;
        s.progress = false;
        s.messages = mbd::MessageLog::silent();
        mbd::simulate(model, mbd::test::shared_registry(), s, {});
    } catch (const std::exception& e) {
        return e.what();
    }
    return "";
}

TEST(JointFriction, RefusedWhereTheLoopIsNotSolvedAndBadInputNamed) {
    const std::string good = pin_scene(0.1);
    EXPECT_EQ(error_of(good), "");
    for (const char* formulation : {"embedding", "amalgamated", "hamiltonian"}) {
        const std::string m = error_of(good, formulation);
        EXPECT_NE(m.find("force 'bearing' (type rotational_friction) takes its load from the reaction of joint 'axle'"),
                  std::string::npos) << m;
        EXPECT_NE(m.find("use the augmented formulation"), std::string::npos) << m;
        EXPECT_NE(m.find("joint-friction.yaml"), std::string::npos) << m;
    }
    const std::string alpha = error_of(good, "augmented", "generalized_alpha");
    EXPECT_NE(alpha.find("generalized_alpha integrator does not solve"), std::string::npos) << alpha;
    auto with = [&](const std::string& from, const std::string& to) { return mbd::test::replaced(good, from, to); };
    const struct {
        std::string from, to, expected;
    } cases[] = {
        {"load_joint: axle", "load_joint: shaft", "'load_joint' names undefined joint 'shaft'"},
        {"load_joint: axle", "load_joint: axle, normal_force: 10", "give either 'normal_force' or 'load_joint'"},
        {"load_joint: axle, ", "", "missing key 'normal_force'"},
    };
    for (const auto& c : cases) {
        const std::string m = error_of(with(c.from, c.to));
        EXPECT_NE(m.find(c.expected), std::string::npos) << c.to << ": " << m;
        EXPECT_NE(m.find("joint-friction.yaml"), std::string::npos) << m;
        EXPECT_NE(m.find("force 'bearing'"), std::string::npos) << m;
    }
    // a joint between other bodies than the element's
    const std::string m = error_of(
        with("bodies: [wheel, ground], point: [0, 0], radius", "bodies: [wheel, hub], point: [0, 0], radius") +
        "  - {name: hub-drive, type: point_torque, body: hub, torque: 0}\n");
    EXPECT_NE(m.find("does not connect the force's bodies"), std::string::npos) << m;
}

// mbd modes does not solve the reaction loads (its accelerations would take the friction at
// load 0): it refuses the element by name, before any statics, and writes nothing; with a
// fixed normal_force in its place the same scene is linearised.
TEST(JointFriction, ModesRefusesAFrictionLoadedByAJointReaction) {
    const std::string message = "force 'bearing' (type rotational_friction) takes its load from the reaction of joint 'axle'";
    const mbd::Model model = mbd::test::scene(pin_scene(0.0), "joint-friction.yaml");
    mbd::ModelSystem system(model);
    try {
        mbd::linearise(system, model.initial_state(), {});
        ADD_FAILURE() << "linearised a scene with a reaction-loaded friction";
    } catch (const mbd::LinearisationError& e) {
        EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("joint-friction.yaml:"), std::string::npos) << e.what();
    }
    const auto dir = std::filesystem::temp_directory_path() / "mbd_test_joint_friction_modes";
    std::filesystem::create_directories(dir);
    const std::string file = (dir / "pin.yaml").string(), csv = (dir / "modes.csv").string();
    std::filesystem::remove(csv);
    std::ofstream(file) << pin_scene(0.0);
    for (const char* about : {"statics", "initial"}) {
        const mbd::test::CommandResult r =
            mbd::test::run_mbd("modes '" + file + "' --about " + about + " --output '" + csv + "'");
        EXPECT_NE(r.exit_code, 0) << about;
        EXPECT_NE(r.err.find(message), std::string::npos) << about << ": " << r.err;
        EXPECT_NE(r.err.find("pin.yaml:"), std::string::npos) << r.err;
        EXPECT_FALSE(std::filesystem::exists(csv)) << about;
    }
    std::ofstream(file) << mbd::test::replaced(pin_scene(0.0), "load_joint: axle", "normal_force: 19.62");
    const mbd::test::CommandResult fixed = mbd::test::run_mbd("modes '" + file + "' --about initial");
    EXPECT_EQ(fixed.exit_code, 0) << fixed.err;
}

}  // namespace
