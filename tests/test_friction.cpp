// Coulomb friction in dynamics (issue 19, item 3): the coulomb_friction force element
// against closed forms.
//  - Book Ex. 5.6 (L6248-6352; digests/formulations.md 11.7): a 5 kg mass on a spring
//    (k = 5e3 N/m) with kinetic friction mu_k = 0.1, released at x0 = 0.03 m. Each half
//    cycle is a harmonic motion about the offset equilibrium sgn(x_n) F_f / k, so the
//    turning points are x_n = (-1)^n (x0 - 2 n F_f / k) at t_n = n pi / w, and the mass
//    stops at the first turning point where k |x_n| <= mu_s F_n.
//  - A block on an incline: sticks when tan(angle) <= mu_s, slides with
//    a = g (sin - mu_k cos) otherwise.
#include "support/test_support.hpp"

#include <mbd/sdk/coulomb_law.hpp>
#include <mbd/model_system.hpp>
#include <mbd/simulation.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace {

using mbd::test::g17;

constexpr double kPi = 3.14159265358979323846;
constexpr double kG = 9.81;

std::vector<mbd::State> run(const mbd::Model& model, double t_end, double output_step, double tolerance) {
    mbd::SimulationSettings s;
    s.formulation = "augmented";
    s.integrator = "cvode";
    s.integration.tolerance = tolerance;
    s.t_end = t_end;
    s.output_step = output_step;
    s.progress = false;
    s.messages = mbd::MessageLog::silent();
    std::vector<mbd::State> states;
    mbd::simulate(model, mbd::test::shared_registry(), s, [&](const mbd::SimulationSample& sample) {
        states.push_back(sample.state);
        return true;
    });
    return states;
}

// ------------------------------------------------------------------ the law
// The shape the docs promise: exactly mu_s at |v| = v_s and on [v_s, 2 v_s], mu_k beyond
// 9 v_s to double precision, odd, and C1 (one-sided differences agree at the joins).
TEST(CoulombLaw, RisesToTheStaticCoefficientAndFallsToTheKinetic) {
    mbd::friction::CoulombLaw law;
    law.mu_static = 0.4;
    law.mu_kinetic = 0.25;
    law.stiction_velocity = 1e-3;
    const double vs = law.stiction_velocity;
    EXPECT_EQ(law.coefficient(0.0), 0.0);
    EXPECT_DOUBLE_EQ(law.coefficient(vs), 0.4);
    EXPECT_DOUBLE_EQ(law.coefficient(1.5 * vs), 0.4);
    EXPECT_DOUBLE_EQ(law.coefficient(2.0 * vs), 0.4);
    EXPECT_EQ(law.coefficient(9.0 * vs), 0.25);
    EXPECT_EQ(law.coefficient(-50.0 * vs), -0.25);
    for (double v : {0.3 * vs, 1.7 * vs, 3.0 * vs}) EXPECT_EQ(law.coefficient(-v), -law.coefficient(v));
    double peak = 0.0;
    for (int k = 0; k <= 4000; ++k) peak = std::max(peak, law.coefficient(k * 1e-2 * vs));
    EXPECT_DOUBLE_EQ(peak, 0.4);  // never above mu_s: the breakaway load is mu_s F_n
    const double h = 1e-7 * vs;
    for (double join : {vs, 2.0 * vs}) {
        const double left = (law.coefficient(join) - law.coefficient(join - h)) / h;
        const double right = (law.coefficient(join + h) - law.coefficient(join)) / h;
        EXPECT_NEAR(left, right, 1e-4 / vs) << join;
    }
    EXPECT_NEAR((law.coefficient(h) - law.coefficient(-h)) / (2 * h), 1.5 * 0.4 / vs, 1e-6 / vs);  // slope at 0
}

// ------------------------------------------------------------------ Ex. 5.6
struct Oscillator {
    double m = 5.0, k = 5e3, mu = 0.1, x0 = 0.03;
    double normal() const { return m * kG; }
    double friction() const { return mu * normal(); }  // F_f = 4.905 N
    double w() const { return std::sqrt(k / m); }       // 31.6228 rad/s
};

// The block slides on a prismatic guide along x; the spring joins it to the ground point
// (-1, 0) with rest length 1 (so its force is -k x); the friction element holds the
// normal load m g (no gravity in the scene: the guide would carry it anyway).
std::string oscillator_scene(const Oscillator& o, double stiction_velocity) {
    return "name: ex5-6\ndimension: planar\n"
           "bodies:\n  - {name: block, mass: " + g17(o.m) + ", inertia: 0.01, position: [" + g17(o.x0) + ", 0]}\n"
           "joints:\n  - {name: guide, type: prismatic, bodies: [ground, block], point: [0, 0], axis: [1, 0]}\n"
           "forces:\n"
           "  - {name: spring, type: spring_damper, bodies: [ground, block], points: [[-1, 0], [0, 0]],"
           " stiffness: " + g17(o.k) + ", rest_length: 1}\n"
           "  - {name: dry, type: coulomb_friction, bodies: [block, ground], point: [" + g17(o.x0) + ", 0], axis: [1, 0],"
           " normal_force: " + g17(o.normal()) + ", static_friction: " + g17(o.mu) + ", kinetic_friction: " +
           g17(o.mu) + ", stiction_velocity: " + g17(stiction_velocity) + "}\n";
}

TEST(CoulombFriction, BookExample5_6TurningPointsHalfCyclesAndRest) {
    const Oscillator o;
    const double drop = 2.0 * o.friction() / o.k;  // 1.962e-3 m per half cycle
    EXPECT_NEAR(drop, 1.962e-3, 1e-12);
    // the closed form: the number of half cycles before rest (the digest: 15)
    int half_cycles = 0;
    while (o.k * std::abs(o.x0 - half_cycles * drop) > o.friction()) ++half_cycles;
    EXPECT_EQ(half_cycles, 15);
    const double t_half = kPi / o.w();  // 0.099346 s
    const int per_half = 40;
    const double t_rest = half_cycles * t_half;
    const auto states = run(mbd::test::scene(oscillator_scene(o, 1e-9)), t_rest + 1.2, t_half / per_half, 1e-12);
    ASSERT_GT(states.size(), static_cast<size_t>(per_half * half_cycles + 1));
    auto x_at = [&](int half) { return states[half * per_half].q[0]; };
    // the digest's corrected values at the first two turning points
    EXPECT_NEAR(x_at(1), -0.028038, 1e-6);
    EXPECT_NEAR(x_at(2), 0.026076, 1e-6);
    double worst_turning = 0.0;
    for (int n = 0; n <= half_cycles; ++n) {
        const double exact = (n % 2 ? -1.0 : 1.0) * (o.x0 - n * drop);
        worst_turning = std::max(worst_turning, std::abs(x_at(n) - exact));
        EXPECT_NEAR(states[n * per_half].t, n * t_half, 1e-12);
    }
    std::printf("Ex. 5.6: worst turning-point error over %d half cycles %.3e m\n", half_cycles, worst_turning);
    EXPECT_LT(worst_turning, 1e-7);
    // still moving just before the last turning point, stuck from then on for more than 1 s
    EXPECT_GT(std::abs(states[half_cycles * per_half - per_half / 2].v[0]), 1e-3);
    double worst_speed = 0.0;
    const double x_rest = states[half_cycles * per_half].q[0];
    for (size_t r = half_cycles * per_half + per_half / 4; r < states.size(); ++r) {
        worst_speed = std::max(worst_speed, std::abs(states[r].v[0]));
        EXPECT_NEAR(states[r].q[0], x_rest, 1e-8);
    }
    std::printf("Ex. 5.6: at rest from t = %.4f s for %.3f s, max |v| %.3e m/s\n", t_rest,
                states.back().t - t_rest - t_half / 4, worst_speed);
    EXPECT_GT(states.back().t - t_rest - t_half / 4, 1.0);
    EXPECT_LT(worst_speed, 1e-9);
    // the energy the friction dissipated, as the diagnostics' kinetic + potential energy show
    // it, against F_f times the distance slid: sum over half cycles of A_n + A_(n+1)
    double path = 0.0;
    for (int n = 0; n < half_cycles; ++n) path += 2.0 * (o.x0 - n * drop) - drop;
    const mbd::Model model = mbd::test::scene(oscillator_scene(o, 1e-9));
    mbd::ModelSystem system(model);
    auto energy = [&](const mbd::State& st) { return system.kinetic_energy(st) + system.potential_energy(st); };
    const double dissipated = energy(states.front()) - energy(states.back());
    std::printf("Ex. 5.6: energy dissipated %.9f J, F_f x distance slid %.9f J\n", dissipated, o.friction() * path);
    EXPECT_NEAR(dissipated, o.friction() * path, 1e-7);
}

// ------------------------------------------------------------------ incline
// A 2 kg block on a guide inclined at `angle`, gravity down; the friction element carries
// the normal load m g cos(angle). Returns the states (q[0..1] position, v along the slope).
std::vector<mbd::State> incline(double angle, double mu_s, double mu_k, double t_end) {
    const double m = 2.0, c = std::cos(angle), s = std::sin(angle);
    const std::string axis = "[" + g17(c) + ", " + g17(s) + "]";
    const std::string yaml =
        "name: incline\ndimension: planar\ngravity: [0, " + g17(-kG) + "]\n"
        "bodies:\n  - {name: block, mass: " + g17(m) + ", inertia: 0.01, position: [0, 0], angle: " + g17(angle) + "}\n"
        "joints:\n  - {name: slope, type: prismatic, bodies: [ground, block], point: [0, 0], axis: " + axis + "}\n"
        "forces:\n"
        "  - {name: dry, type: coulomb_friction, bodies: [block, ground], point: [0, 0], axis: " + axis +
        ", normal_force: " + g17(m * kG * c) + ", static_friction: " + g17(mu_s) + ", kinetic_friction: " + g17(mu_k) +
        ", stiction_velocity: 1e-9}\n";
    return run(mbd::test::scene(yaml), t_end, 0.05, 1e-12);
}
double along(const mbd::State& st, double angle) { return st.q[0] * std::cos(angle) + st.q[1] * std::sin(angle); }
double speed_along(const mbd::State& st, double angle) { return st.v[0] * std::cos(angle) + st.v[1] * std::sin(angle); }

TEST(CoulombFriction, BlockOnAnInclineSticksUpToTheStaticCoefficient) {
    const double mu_s = 0.4, mu_k = 0.3;
    for (double tan_angle : {0.2, 0.39, mu_s}) {
        const double angle = std::atan(tan_angle);
        const auto states = incline(angle, mu_s, mu_k, 1.0);
        double travel = 0.0;
        for (const auto& st : states) travel = std::max(travel, std::abs(along(st, angle)));
        std::printf("incline tan %.3f (mu_s %.2f): travel in 1 s %.3e m\n", tan_angle, mu_s, travel);
        // within the stiction velocity times 1 s (twice that at tan = mu_s: the plateau of the law)
        EXPECT_LT(travel, (tan_angle < mu_s ? 1.0 : 2.0) * 1e-9 + 1e-12) << "tan(angle) = " << tan_angle;
    }
}

TEST(CoulombFriction, BlockOnAnInclineSlidesWithTheKineticCoefficient) {
    const double mu_s = 0.4, mu_k = 0.3;
    for (double tan_angle : {mu_s * 1.001, 0.7, 2.0}) {
        const double angle = std::atan(tan_angle);
        const auto states = incline(angle, mu_s, mu_k, 1.0);
        const double a = kG * (std::sin(angle) - mu_k * std::cos(angle));
        // after the start (the stiction band is crossed in ~1e-8 s) the speed grows at a
        const mbd::State &s1 = states[10], &s2 = states.back();
        const double measured = (speed_along(s1, angle) - speed_along(s2, angle)) / (s2.t - s1.t);  // down the slope
        std::printf("incline tan %.4f: a %.12f, closed form %.12f, error %.2e\n", tan_angle, measured, a,
                    measured - a);
        EXPECT_NEAR(measured, a, 1e-8) << "tan(angle) = " << tan_angle;
        EXPECT_LT(along(s2, angle), 0.0);  // down the slope (the axis points up it)
    }
}

// ------------------------------------------------------------------ a pin with friction
// A wheel (J = 0.5 kg m^2) on a revolute joint to the ground, a torque T about the pin
// and the pin's friction: radius 0.02 m, load 500 N, mu_s 0.3, mu_k 0.2, preload 0.5 N m,
// so breakaway M_s = 0.3 * 0.02 * 500 + 0.5 = 3.5 N m and slipping M_k = 2.5 N m.
std::vector<mbd::State> pin(double torque) {
    const std::string yaml =
        "name: pin\ndimension: planar\n"
        "bodies:\n  - {name: wheel, mass: 2, inertia: 0.5, position: [0, 0]}\n"
        "joints:\n  - {name: axle, type: revolute, bodies: [ground, wheel], point: [0, 0]}\n"
        "forces:\n"
        "  - {name: motor, type: point_torque, body: wheel, torque: " + g17(torque) + "}\n"
        "  - {name: bearing, type: rotational_friction, bodies: [wheel, ground], point: [0, 0], radius: 0.02,"
        " normal_force: 500, static_friction: 0.3, kinetic_friction: 0.2, preload: 0.5, stiction_velocity: 1e-9}\n";
    return run(mbd::test::scene(yaml), 1.0, 0.05, 1e-12);
}

TEST(RotationalFriction, PinUnderATorqueBelowBreakawayDoesNotTurn) {
    const double breakaway = 0.3 * 0.02 * 500 + 0.5;
    for (double torque : {1.0, 3.4, breakaway, -3.4}) {
        double turned = 0.0;
        for (const auto& st : pin(torque)) turned = std::max(turned, std::abs(st.q[2]));
        std::printf("pin, torque %.3f N m (breakaway %.3f): turned %.3e rad in 1 s\n", torque, breakaway, turned);
        EXPECT_LT(turned, (std::abs(torque) < breakaway ? 1.0 : 2.0) * 1e-9 + 1e-12) << torque;
    }
}

TEST(RotationalFriction, PinAboveBreakawaySlipsWithTheKineticMoment) {
    const double kinetic = 0.2 * 0.02 * 500 + 0.5, J = 0.5;
    for (double torque : {3.51, 5.0, -8.0}) {
        const auto states = pin(torque);
        const mbd::State &a = states[4], &b = states.back();
        const double measured = (b.v[2] - a.v[2]) / (b.t - a.t);
        const double exact = (torque - (torque > 0 ? kinetic : -kinetic)) / J;
        std::printf("pin, torque %.2f: angular acceleration %.12f, closed form %.12f\n", torque, measured, exact);
        EXPECT_NEAR(measured, exact, 1e-8) << torque;
    }
}

// ------------------------------------------------------------------ the example scenes
// scenes/examples/force-*-friction.yaml: the planar block sliding down its incline and the
// spatial flywheel slipping in its bearing, against their closed forms.
TEST(Friction, ExampleScenesMatchTheirClosedForms) {
    {
        const auto states = run(mbd::test::load("examples/force-coulomb-friction.yaml"), 1.0, 0.05, 1e-12);
        const double angle = std::atan(0.7);
        const double a = kG * (std::sin(angle) - 0.3 * std::cos(angle));
        const mbd::State &s1 = states[4], &s2 = states.back();
        EXPECT_NEAR((speed_along(s1, angle) - speed_along(s2, angle)) / (s2.t - s1.t), a, 1e-8);
    }
    {
        const mbd::Model model = mbd::test::load("examples/force-rotational-friction.yaml");
        const auto states = run(model, 1.0, 0.05, 1e-12);
        const mbd::State &s1 = states[4], &s2 = states.back();
        // spatial velocities: [Rdot, omega_bar (body axes)]; the hinge is the body z axis
        const double alpha = (s2.v[5] - s1.v[5]) / (s2.t - s1.t);
        std::printf("spatial flywheel in its bearing: %.12f rad/s^2 (closed form 5)\n", alpha);
        EXPECT_NEAR(alpha, (5.0 - (0.2 * 0.02 * 500 + 0.5)) / 0.5, 1e-8);
        EXPECT_LT(std::abs(s2.v[3]) + std::abs(s2.v[4]), 1e-9);  // it turns about the hinge only
    }
}

// ------------------------------------------------------------------ the plugin check
// Its Jacobians against central differences, planar and spatial, with the random sliding
// speeds of the check inside the stiction band (v_s = 5 m/s), on the plateau and beyond.
TEST(Friction, BothPluginsPassThePluginCheck) {
    for (const char* type : {"coulomb_friction", "rotational_friction"}) {
        const std::string lib =
            (mbd::test::build_plugin_dir() / ("libmbd_force_" + std::string(type) + ".so")).string();
        const std::string keys = std::string(type) == "rotational_friction"
                                     ? " --params 'radius: 0.02' --params 'normal_force: 100' --params 'preload: 0.1'"
                                     : " --params 'normal_force: 10'";
        for (const char* vs : {"5", "0.5", "1e-3"}) {
            const auto r = mbd::test::run_mbd("plugin check " + lib + keys +
                                              " --params 'static_friction: 0.3' --params 'kinetic_friction: 0.2'"
                                              " --params 'stiction_velocity: " + vs + "'");
            EXPECT_EQ(r.exit_code, 0) << type << " " << r.out << r.err;
            EXPECT_NE(r.out.find("2 checked, 0 failed"), std::string::npos) << r.out;
        }
    }
}

// ------------------------------------------------------------------ bad input
std::string error_of(const std::string& yaml) {
    try {
        const mbd::Model model = mbd::test::scene(yaml, "friction.yaml");
        run(model, 0.01, 0.005, 1e-8);
    } catch (const std::exception& e) {
        return e.what();
    }
    return "";
}

TEST(CoulombFriction, BadInputIsNamedWithItsKey) {
    const Oscillator o;
    const std::string good = oscillator_scene(o, 1e-6);
    auto with = [&](const std::string& from, const std::string& to) { return mbd::test::replaced(good, from, to); };
    const struct {
        std::string from, to, expected;
    } cases[] = {
        {"kinetic_friction: 0.10000000000000001", "kinetic_friction: 0.2", "must not exceed 'static_friction'"},
        {"stiction_velocity: 9.9999999999999995e-07", "stiction_velocity: 0", "'stiction_velocity' must be positive"},
        {"normal_force: 49.050000000000004,", "", "missing key 'normal_force'"},
        {"normal_force: 49.050000000000004", "normal_force: -1", "'normal_force' must not be negative"},
        {"static_friction: 0.10000000000000001", "static_friction: -0.1", "'static_friction' must not be negative"},
        {"bodies: [block, ground], point", "bodies: [block], point", "two bodies"},
    };
    for (const auto& c : cases) {
        const std::string m = error_of(with(c.from, c.to));
        EXPECT_NE(m.find(c.expected), std::string::npos) << c.to << ": " << m;
        EXPECT_NE(m.find("friction.yaml"), std::string::npos) << m;
        if (c.expected != "two bodies") EXPECT_NE(m.find("force 'dry'"), std::string::npos) << m;
    }
    // a normal load that turns negative during the run stops it, naming the element
    const std::string m = error_of(with("normal_force: 49.050000000000004",
                                        "normal_force: {type: harmonic, amplitude: 1, frequency: 1000}"));
    EXPECT_NE(m.find("force 'dry': normal_force is negative"), std::string::npos) << m;
}

}  // namespace
