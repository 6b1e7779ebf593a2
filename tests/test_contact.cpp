// Compliant contact with friction (issue 19, item 4): the sphere_plane, sphere_sphere,
// circle_line and circle_circle force elements (sdk/include/mbd/sdk/contact.hpp) against
// independent oracles:
//  - a ball dropped on a plane: its energy after the bounce and its rebound speed against a
//    1-DOF contact ODE m x'' = -m g + F_n(r - x, -x') integrated here (RK4, tiny step) from
//    the moment of contact (the fall before it is the closed form v0 = sqrt(2 g h));
//    undamped, the energy is conserved across the bounce;
//  - a ball resting on the plane: the static penetration (m g / k)^(1/n);
//  - two equal balls colliding head-on: momentum conserved to roundoff, and undamped, the
//    velocities exchange;
//  - a ball sliding without spin: it decelerates at mu g and rolls from v = 5/7 v0;
//  - Jacobians against central differences (core/src/analyses/derivative_check.cpp), and the plugin check;
//  - bad input named by its key.
#include "support/test_support.hpp"

// the elements themselves (header-only, SDK-only), for their gap_and_rate member
#include "../plugins/forces/contact/plane_contact.hpp"
#include "../plugins/forces/contact/sphere_contact.hpp"

#include <mbd/body_poses.hpp>
#include <mbd/derivative_check.hpp>
#include <mbd/simulation.hpp>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

namespace {

using mbd::test::g17;

constexpr double kG = 9.81;

mbd::SimulationResult run(const mbd::Model& model, const std::string& integrator, double t_end, double tolerance,
                          const std::function<void(const mbd::State&)>& sample = nullptr) {
    mbd::SimulationSettings s;
    s.formulation = "augmented";
    s.integrator = integrator;
    s.integration.tolerance = tolerance;
    s.t_end = t_end;
    s.output_step = t_end / 200;
    s.progress = false;
    s.messages = mbd::MessageLog::silent();
    return mbd::simulate(model, mbd::test::shared_registry(), s, [&](const mbd::SimulationSample& x) {
        if (sample) sample(x.state);
        return true;
    });
}

// ------------------------------------------------------------------ the 1-DOF oracle
struct Ball {
    double m = 1.0, r = 0.1, k = 1e6, n = 1.5, c = 0.0;
    // F_n of the Hunt-Crossley law written again here: k d^n + c d^n d', never tensile
    double normal_force(double x, double xdot) const {
        const double d = r - x;
        if (d <= 0.0) return 0.0;
        return std::max(0.0, k * std::pow(d, n) + c * std::pow(d, n) * (-xdot));
    }
};

// The height x of the centre over the plane through the contact, from touching down at speed v0
// until the ball has left the plane; returns (x, x') one step into the flight. (With gravity 0
// and the reduced mass, x - r is the gap of a head-on hit of two balls.)
std::pair<double, double> bounce(const Ball& b, double v0, double gravity = kG) {
    auto f = [&](double x, double v) { return std::make_pair(v, -gravity + b.normal_force(x, v) / b.m); };
    double x = b.r, v = -v0;
    const double h = 2e-7;
    bool left = false;
    while (!left) {
        const auto k1 = f(x, v);
        const auto k2 = f(x + 0.5 * h * k1.first, v + 0.5 * h * k1.second);
        const auto k3 = f(x + 0.5 * h * k2.first, v + 0.5 * h * k2.second);
        const auto k4 = f(x + h * k3.first, v + h * k3.second);
        const bool inside = x < b.r;
        x += h / 6 * (k1.first + 2 * k2.first + 2 * k3.first + k4.first);
        v += h / 6 * (k1.second + 2 * k2.second + 2 * k3.second + k4.second);
        left = inside && x >= b.r && v > 0.0;
    }
    return {x, v};
}

// A solid ball over the ground plane z = 0 (or the line y = 0), released at rest.
std::string drop_scene(const std::string& type, const Ball& b, double height, const std::string& damping_keys) {
    const bool planar = type == "circle_line";
    const double J = 0.4 * b.m * b.r * b.r;
    return std::string("dimension: ") + (planar ? "planar" : "spatial") + "\n" +
           "gravity: " + (planar ? "[0, -9.81]" : "[0, 0, -9.81]") + "\n" +
           "bodies:\n  - {name: ball, mass: " + g17(b.m) + ", inertia: " +
           (planar ? g17(J) : "[" + g17(J) + ", " + g17(J) + ", " + g17(J) + "]") + ", position: " +
           (planar ? "[0, " + g17(height) + "]" : "[0, 0, " + g17(height) + "]") + "}\n" +
           "forces:\n  - {name: floor, type: " + type + ", bodies: [ground, ball], normal: " +
           (planar ? "[0, 1]" : "[0, 0, 1]") + ", radius: " + g17(b.r) + ", stiffness: " + g17(b.k) +
           ", exponent: " + g17(b.n) + damping_keys + "}\n";
}

double energy(const mbd::Model& model, const mbd::State& s, const Ball& b) {
    const bool planar = model.dimension == mbd::Dimension::Planar;
    const double height = planar ? s.q[1] : s.q[2];
    const double J = 0.4 * b.m * b.r * b.r;
    const int nt = planar ? 2 : 3;
    return 0.5 * b.m * s.v.head(nt).squaredNorm() + 0.5 * J * s.v.tail(planar ? 1 : 3).squaredNorm() +
           b.m * kG * height;
}

// ------------------------------------------------------------------ the bounce
TEST(Contact, BounceOnAPlaneLosesTheEnergyOfTheContactOde) {
    const double drop = 0.05;  // fall height to the contact: v0 = sqrt(2 g h) = 0.9905 m/s
    const double v0 = std::sqrt(2 * kG * drop);
    for (const char* type : {"sphere_plane", "circle_line"}) {
        for (double e : {0.8, 0.5}) {
            Ball b;
            b.c = 3.0 * b.k * (1.0 - e * e) / (4.0 * v0);  // the Lankarani-Nikravesh relation, here for the oracle
            const std::string keys = ", restitution: " + g17(e) + ", impact_velocity: " + g17(v0);
            const mbd::Model model = mbd::test::scene(drop_scene(type, b, b.r + drop, keys));
            const auto [x, v] = bounce(b, v0);
            const double E0 = b.m * kG * (b.r + drop), E_ode = 0.5 * b.m * v * v + b.m * kG * x;
            // t_end: after the bounce (~0.11 s), before the next touch-down (> 0.2 s for e >= 0.5)
            const auto result = run(model, "dopri5", 0.16, 1e-11);
            // the contact's onset and end are located events (steps end on them): the touch-down
            // after the free fall from the drop height, sqrt(2 h / g)
            ASSERT_EQ(result.events.size(), 2u) << type << ": touch-down and lift-off";
            EXPECT_NEAR(result.events[0].time, std::sqrt(2 * drop / kG), 1e-9) << type;
            EXPECT_NEAR(result.events[0].rate_before, -v0, 1e-8) << type;
            const double E_sim = energy(model, result.final_state, b);
            const double rebound_ode = std::sqrt(2 * (E_ode / b.m - kG * b.r));
            const double rebound_sim = std::sqrt(2 * (E_sim / b.m - kG * b.r));
            std::printf("%s e = %.1f: rebound %.9f m/s (ODE %.9f), energy lost %.9f J (ODE %.9f), e_eff %.5f\n", type,
                        e, rebound_sim, rebound_ode, E0 - E_sim, E0 - E_ode, rebound_sim / v0);
            EXPECT_NEAR(rebound_sim, rebound_ode, 1e-6 * rebound_ode) << type;
            EXPECT_NEAR(E0 - E_sim, E0 - E_ode, 1e-6 * (E0 - E_ode)) << type;
            // still in the air: the element's energy is zero there
            const double height = model.dimension == mbd::Dimension::Planar ? result.final_state.q[1]
                                                                             : result.final_state.q[2];
            EXPECT_GT(height, b.r);
        }
    }
}

TEST(Contact, UndampedBounceConservesEnergy) {
    for (const char* type : {"sphere_plane", "circle_line"}) {
        Ball b;
        const double drop = 0.05, E0 = b.m * kG * (b.r + drop);
        const mbd::Model model = mbd::test::scene(drop_scene(type, b, b.r + drop, ""));
        double worst = 0.0;
        bool touched = false;
        // the element's potential k d^(n+1)/(n+1) counts while the ball is in contact
        run(model, "dopri5", 0.2, 1e-11, [&](const mbd::State& s) {
            const double height = model.dimension == mbd::Dimension::Planar ? s.q[1] : s.q[2];
            const double d = b.r - height;
            touched = touched || d > 0.0;
            const double V = d > 0.0 ? b.k * std::pow(d, b.n + 1) / (b.n + 1) : 0.0;
            worst = std::max(worst, std::abs(energy(model, s, b) + V - E0) / E0);
        });
        std::printf("%s undamped: worst relative energy error %.3e\n", type, worst);
        EXPECT_TRUE(touched);
        EXPECT_LT(worst, 1e-8) << type;
    }
}

// ------------------------------------------------------------------ rest
TEST(Contact, RestingBallPenetratesByTheStaticDeflection) {
    for (const char* type : {"sphere_plane", "circle_line"}) {
        for (double n : {1.5, 1.0}) {
            Ball b;
            b.k = 1e5;
            b.n = n;
            const double delta = std::pow(b.m * kG / b.k, 1.0 / n);  // 2.13e-3 m (n = 1.5), 9.81e-5 m (n = 1)
            // damping near critical for the contact's linearized stiffness n k delta^(n-1)
            const double omega = std::sqrt(n * b.k * std::pow(delta, n - 1) / b.m);
            const double c = omega * b.m / std::pow(delta, n);
            const mbd::Model model = mbd::test::scene(drop_scene(type, b, b.r, ", damping: " + g17(c)));
            const auto result = run(model, "dopri5", 0.5, 1e-11);
            const double height = model.dimension == mbd::Dimension::Planar ? result.final_state.q[1]
                                                                             : result.final_state.q[2];
            std::printf("%s n = %.1f: penetration %.12e m (closed form %.12e)\n", type, n, b.r - height, delta);
            EXPECT_NEAR(b.r - height, delta, 1e-7 * delta) << type;
        }
    }
}

// ------------------------------------------------------------------ two balls
std::string collision_scene(const std::string& type, const std::string& damping_keys) {
    const bool planar = type == "circle_circle";
    auto vec = [&](double x) { return planar ? "[" + g17(x) + ", 0]" : "[" + g17(x) + ", 0, 0]"; };
    const std::string inertia = planar ? "0.004" : "[0.004, 0.004, 0.004]";
    return std::string("dimension: ") + (planar ? "planar" : "spatial") + "\n" +
           "bodies:\n"
           "  - {name: a, mass: 1, inertia: " + inertia + ", position: " + vec(0.0) + ", velocity: " + vec(1.0) + "}\n"
           "  - {name: b, mass: 1, inertia: " + inertia + ", position: " + vec(0.25) + "}\n"
           "forces:\n  - {name: hit, type: " + type + ", bodies: [a, b], radii: [0.1, 0.1], stiffness: 1e6" +
           damping_keys + "}\n";
}

TEST(Contact, HeadOnCollisionConservesMomentumAndUndampedExchangesVelocities) {
    for (const char* type : {"sphere_sphere", "circle_circle"}) {
        for (const char* keys : {"", ", damping: 2e5"}) {
            const mbd::Model model = mbd::test::scene(collision_scene(type, keys));
            const int nvb = mbd::velocities_per_body(model.dimension);
            double worst = 0.0;
            const auto result = run(model, "dopri5", 0.1, 1e-11, [&](const mbd::State& s) {
                const int nt = model.dimension == mbd::Dimension::Planar ? 2 : 3;  // masses 1 kg
                Eigen::VectorXd p = s.v.segment(0, nt) + s.v.segment(nvb, nt);
                p[0] -= 1.0;
                worst = std::max(worst, p.norm());
            });
            const double va = result.final_state.v[0], vb = result.final_state.v[nvb];
            std::printf("%s%s: after the hit v_a = %.9f, v_b = %.9f m/s; momentum error %.2e\n", type, keys, va, vb,
                        worst);
            EXPECT_LT(worst, 1e-12) << type;
            if (std::string(keys).empty()) {
                EXPECT_NEAR(va, 0.0, 1e-6) << type;
                EXPECT_NEAR(vb, 1.0, 1e-6) << type;
            } else {
                EXPECT_GT(va, 0.01) << type;  // an inelastic hit: a follows b
                EXPECT_LT(vb - va, 0.99) << type;
            }
        }
    }
}

// The restitution relations are approximate (derived for e near 1): a gravity-free head-on hit of
// two 1 kg balls at the impact velocity they were given separates at the speed of the 1-DOF
// ODE of the gap (reduced mass 0.5 kg; to 1e-6), which is about e times it: within 0.015 for
// e = 0.9 (0.913 Lankarani-Nikravesh, 0.909 Hunt-Crossley), while for e = 0.7 both lose too
// little (0.796, 0.768: the known over-prediction of these relations away from e = 1).
TEST(Contact, RestitutionRelationsGiveAboutTheRequestedCoefficient) {
    for (const char* model_name : {"lankarani_nikravesh", "hunt_crossley"}) {
        for (double e : {0.9, 0.7}) {
            const std::string keys = ", restitution: " + g17(e) + ", impact_velocity: 1, restitution_model: " + model_name;
            const mbd::Model model = mbd::test::scene(collision_scene("sphere_sphere", keys));
            const auto result = run(model, "dopri5", 0.1, 1e-11);
            const double separation = result.final_state.v[6] - result.final_state.v[0];  // approach speed 1 m/s
            Ball gap;  // the relative motion: reduced mass, the law's k, n = 1.5 and c of the relation
            gap.m = 0.5;
            gap.k = 1e6;
            gap.c = std::string(model_name) == "hunt_crossley" ? 1.5 * gap.k * (1 - e) : 0.75 * gap.k * (1 - e * e);
            const double separation_ode = bounce(gap, 1.0, 0.0).second;
            std::printf("%s e = %.1f: separation speed %.9f m/s (ODE %.9f)\n", model_name, e, separation,
                        separation_ode);
            EXPECT_NEAR(separation, separation_ode, 1e-6 * separation_ode) << model_name;
            if (e > 0.8) {
                EXPECT_NEAR(separation, e, 0.015) << model_name;
            } else {
                EXPECT_GT(separation, e) << model_name;
                EXPECT_LT(separation, e + 0.1) << model_name;
            }
        }
    }
}

// ------------------------------------------------------------------ friction
// A solid ball (J = 2/5 m r^2) set sliding at v0 without spin on the ground plane, resting at its
// static penetration: friction mu m g decelerates it (v = v0 - mu g t) and spins it up
// (J w' = mu m g h, h = r - delta the lever arm of the contact point) until v = w h, at
// v = v0 5 h^2 / (2 r^2 + 5 h^2) (= 5/7 v0 for h = r), t = (v0 - v) / (mu g); then it rolls.
// The regularized law (v_s = 1e-5 m/s) is exactly mu beyond 9 v_s, so the sliding
// deceleration is exact; the roll starts within the stiction band, so the rolling speed is
// within a few v_s of the rigid one (asserted to 20 v_s).
TEST(Contact, SlidingBallDeceleratesAtMuGAndRollsAtFiveSevenths) {
    for (const char* type : {"sphere_plane", "circle_line"}) {
        const bool planar = std::string(type) == "circle_line";
        Ball b;
        b.k = 1e7;
        const double mu = 0.3, v0 = 1.0, vs = 1e-5;
        const double delta = std::pow(b.m * kG / b.k, 1.0 / b.n), h = b.r - delta;
        const double v_roll = v0 * 5 * h * h / (2 * b.r * b.r + 5 * h * h);
        const double t_roll = (v0 - v_roll) / (mu * kG);
        std::string yaml = drop_scene(type, b, h,
                                      ", damping: 1e4, static_friction: " + g17(mu) + ", stiction_velocity: " + g17(vs));
        const std::string at = "position: ";
        yaml.insert(yaml.find(at), planar ? "velocity: [1, 0], " : "velocity: [1, 0, 0], ");
        const mbd::Model model = mbd::test::scene(yaml);
        std::vector<mbd::State> states;
        run(model, "cvode", 1.5 * t_roll, 1e-10, [&](const mbd::State& s) { states.push_back(s); });
        // sliding: samples at 0.2 t_roll and 0.8 t_roll (200 samples over 1.5 t_roll)
        const mbd::State &s1 = states[27], &s2 = states[107];
        const double decel = (s1.v[0] - s2.v[0]) / (s2.t - s1.t);
        const double v_end = states.back().v[0];
        // the rolling condition at the end: the contact point does not slip
        const double w = planar ? states.back().v[2] : states.back().v[4];  // about z (planar) / y (spatial)
        const double slip = planar ? v_end + w * h : v_end - w * h;
        std::printf("%s: deceleration %.10f m/s^2 (mu g %.10f), rolling at %.8f m/s (rigid %.8f, 5/7 v0 %.8f), "
                    "slip %.2e m/s\n",
                    type, decel, mu * kG, v_end, v_roll, 5.0 / 7.0 * v0, slip);
        EXPECT_NEAR(decel, mu * kG, 1e-6 * mu * kG) << type;
        EXPECT_NEAR(v_end, v_roll, 20 * vs) << type;
        EXPECT_NEAR(v_end, 5.0 / 7.0 * v0, 1e-3) << type;  // the lever arm h = r - delta: 4e-4 m/s here
        EXPECT_LT(std::abs(slip), vs) << type;
    }
}

// ------------------------------------------------------------------ Jacobians
// Every type with damping and friction, the plane or the first sphere on a moving, turning
// body, and the contact closed at every random state of the check (penetrations of ~0.5 m
// against the check's spread of 0.3 m): dQ/dq and dQ/dv against central differences; and
// undamped, frictionless, Q = -dV/dq.
std::string jacobian_scene(const std::string& type, const std::string& law) {
    const bool planar = type == "circle_line" || type == "circle_circle";
    const bool plane = type == "circle_line" || type == "sphere_plane";
    std::string s = std::string("dimension: ") + (planar ? "planar" : "spatial") + "\nbodies:\n";
    if (planar)
        s += "  - {name: a, mass: 1.3, inertia: 0.2, position: [0.3, 0.1], angle: 0.2, velocity: [0.3, -0.2], "
             "angular_velocity: 1.1}\n"
             "  - {name: b, mass: 0.7, inertia: 0.1, position: [0.5, 1.2], angle: -0.4, velocity: [-0.1, 0.4], "
             "angular_velocity: -2}\n";
    else
        s += "  - {name: a, mass: 1.3, inertia: [0.2, 0.3, 0.4], position: [0.3, 0.1, 0.2], "
             "orientation: {axis: [1, 2, 3], angle: 0.5}, velocity: [0.3, -0.2, 0.1], angular_velocity: [1, -2, 0.5]}\n"
             "  - {name: b, mass: 0.7, inertia: [0.1, 0.2, 0.25], position: [0.5, 0.3, 1.2], "
             "orientation: {axis: [-1, 0.5, 2], angle: 1.1}, velocity: [-0.1, 0.4, 0.2], angular_velocity: [0.3, 1, -1]}\n";
    const std::string points = planar ? "[[0.1, -0.05], [0.05, 0.1]]" : "[[0.1, -0.05, 0.02], [0.05, 0.1, -0.03]]";
    s += "forces:\n  - {name: touch, type: " + type + ", bodies: [a, b], points: " + points + ", stiffness: 300, " + law;
    if (plane) s += std::string(", radius: 1.5, normal: ") + (planar ? "[0.1, 1]" : "[0.1, 0.2, 1]");
    else s += ", radii: [0.7, 0.9]";
    return s + "}\n";
}

TEST(Contact, JacobiansMatchCentralDifferences) {
    for (const char* type : {"sphere_plane", "circle_line", "sphere_sphere", "circle_circle"}) {
        for (const char* vs : {"0.5", "1e-2"}) {
            const mbd::Model model = mbd::test::scene(jacobian_scene(
                type, std::string("exponent: 1.5, damping: 20, static_friction: 0.4, kinetic_friction: 0.25, "
                                  "stiction_velocity: ") + vs));
            std::mt19937 rng(7);
            const mbd::DerivativeErrors e = mbd::check_force_derivatives(model, model.forces[0], rng, 8);
            std::printf("%s v_s = %s: dQ/dq %.2e, dQ/dv %.2e\n", type, vs, e.jacobian, e.velocity_jacobian);
            EXPECT_TRUE(e.finite) << type;
            EXPECT_LT(e.jacobian, 1e-6) << type << " " << e.worst_state;
            EXPECT_LT(e.velocity_jacobian, 1e-6) << type << " " << e.worst_state;
            EXPECT_FALSE(model.forces[0].force->is_conservative());
        }
        const mbd::Model elastic = mbd::test::scene(jacobian_scene(type, "exponent: 1.3"));
        ASSERT_TRUE(elastic.forces[0].force->is_conservative()) << type;
        std::mt19937 rng(11);
        const mbd::DerivativeErrors e = mbd::check_force_derivatives(elastic, elastic.forces[0], rng, 8);
        std::printf("%s elastic: Q + dV/dq %.2e\n", type, e.potential);
        EXPECT_LT(e.potential, 1e-6) << type;
        EXPECT_LT(e.jacobian, 1e-6) << type;
    }
}

TEST(Contact, PluginsPassThePluginCheck) {
    for (const char* type : {"sphere_plane", "circle_line", "sphere_sphere", "circle_circle"}) {
        const bool plane = std::string(type) == "sphere_plane" || std::string(type) == "circle_line";
        const bool planar = std::string(type) == "circle_line" || std::string(type) == "circle_circle";
        // shapes that overlap at the check's random geometry, by less than the (smaller) radius,
        // which a contact refuses beyond: the centres 0.585 m (spatial) and 0.65 to 0.7 m (planar)
        // apart, the sphere's centre above the plane
        const std::string shape = !plane ? " --params 'radii: [0.4, 0.5]'"
                                  : planar ? " --params 'radius: 10' --params 'normal: [0.6, 0.8]'"
                                           : " --params 'radius: 10' --params 'normal: [-0.3, -0.4, -0.866]'";
        const std::string lib = (mbd::test::build_plugin_dir() / ("libmbd_force_" + std::string(type) + ".so")).string();
        const auto r = mbd::test::run_mbd("plugin check " + lib + shape +
                                          " --params 'stiffness: 100' --params 'damping: 2'"
                                          " --params 'static_friction: 0.3' --params 'stiction_velocity: 0.5'");
        EXPECT_EQ(r.exit_code, 0) << type << " " << r.out << r.err;
        EXPECT_NE(r.out.find("1 checked, 0 failed"), std::string::npos) << r.out;
    }
}

// ------------------------------------------------------------------ the gap, and no force apart
TEST(Contact, SeparatedBodiesFeelNoForceAndNoJacobian) {
    for (const char* type : {"sphere_plane", "sphere_sphere"}) {
        // lift body b by 5 m: every shape is apart
        std::string yaml = jacobian_scene(type, "damping: 20, static_friction: 0.4");
        yaml.replace(yaml.find("1.2], orientation: {axis: [-1"), 3, "6.2");
        const mbd::Model model = mbd::test::scene(yaml);
        std::mt19937 rng(3);
        const mbd::State s = mbd::random_state(model, rng, 0.3, 3.0, 0.0);
        mbd::BodyPoses poses(model);
        poses.update(s);
        const mbd::ForceInstance& f = model.forces[0];
        Eigen::VectorXd Q = Eigen::VectorXd::Zero(12);
        Eigen::MatrixXd Kq = Eigen::MatrixXd::Zero(12, 12), Kv = Kq;
        f.force->evaluate(poses.view(f.bodies, s.t), Q);
        f.force->jacobians(poses.view(f.bodies, s.t), Kq, Kv);
        EXPECT_EQ(Q.norm(), 0.0) << type;
        EXPECT_EQ(Kq.norm() + Kv.norm(), 0.0) << type;
        EXPECT_EQ(f.force->potential_energy(poses.view(f.bodies, s.t)), 0.0) << type;
    }
}

// ------------------------------------------------------------------ gap and rate
// The members an event function will watch: the gap against its definition at a state where
// both bodies move and turn, and its rate against a central difference of the gap along the
// motion (constant velocities, constant body-axes angular velocities).
mbd::Param scalar(const std::string& text) {
    mbd::Param p;
    p.text = text;
    p.file = "gap.yaml";
    p.line = 3;
    return p;
}
mbd::Param numbers(const std::vector<double>& values) {
    mbd::Param p = scalar("");
    p.kind = mbd::Param::Kind::List;
    for (double v : values) p.items.push_back(scalar(g17(v)));
    return p;
}

struct Motion {  // a spatial body's pose at t from its pose and velocities at 0
    mbd::Vec3 R, v, w_bar;
    Eigen::Quaterniond q;
    mbd::SpatialBody at(double t) const {
        const double angle = w_bar.norm() * t;
        const Eigen::Quaterniond qt = q * Eigen::Quaterniond(Eigen::AngleAxisd(angle, w_bar.normalized()));
        mbd::SpatialBody b;
        b.set(R + v * t, mbd::Vec4(qt.w(), qt.x(), qt.y(), qt.z()), v, w_bar);
        return b;
    }
};

template <class Element>
void expect_gap_and_rate(const Element& element, const Motion& i, const Motion& j, double expected_gap) {
    auto gap_at = [&](double t) {
        const mbd::SpatialBody bi = i.at(t), bj = j.at(t);
        mbd::BodyStates b;
        b.spatial_bodies = {&bi, &bj};
        return element.gap_and_rate(b);
    };
    const double h = 1e-6;
    const mbd::contact::GapAndRate now = gap_at(0.0);
    const double rate = (gap_at(h).gap - gap_at(-h).gap) / (2 * h);
    std::printf("gap %.12f m (definition %.12f), rate %.9f m/s (difference %.9f)\n", now.gap, expected_gap, now.rate,
                rate);
    EXPECT_NEAR(now.gap, expected_gap, 1e-14);
    EXPECT_NEAR(now.rate, rate, 1e-8);
    EXPECT_GT(std::abs(now.rate), 0.1);  // a rate that the turning normal and the motion both feed
}

TEST(Contact, GapAndItsRateForTheEventHook) {
    const Motion i{{0.1, -0.2, 0.3}, {0.4, 0.1, -0.3}, {0.7, -1.1, 0.5},
                   Eigen::Quaterniond(Eigen::AngleAxisd(0.6, mbd::Vec3(1, 2, -1).normalized()))};
    const Motion j{{0.5, 0.2, 1.4}, {-0.2, 0.3, 0.6}, {-0.4, 0.9, 1.3},
                   Eigen::Quaterniond(Eigen::AngleAxisd(1.1, mbd::Vec3(-1, 0.5, 2).normalized()))};
    const mbd::Vec3 ui(0.05, 0.1, -0.02), uj(-0.03, 0.04, 0.06);
    mbd::ForceSpec spec;
    spec.name = "touch";
    spec.dimension = mbd::Dimension::Spatial;
    spec.bodies.resize(2);
    spec.bodies[0].name = "a";
    spec.bodies[1].name = "b";
    spec.markers.resize(2);
    spec.markers[0].u_bar = ui;
    spec.markers[1].u_bar = uj;
    const mbd::SpatialBody bi = i.at(0.0), bj = j.at(0.0);
    // the bodies' initial poses (an element refuses an initial overlap beyond the radius)
    spec.bodies[0].position = bi.R;
    spec.bodies[0].orientation = bi.A;
    spec.bodies[1].position = bj.R;
    spec.bodies[1].orientation = bj.A;
    const mbd::Vec3 P0 = bi.R + bi.A * ui, C = bj.R + bj.A * uj;
    {
        mbd::Param node = scalar("");
        node.kind = mbd::Param::Kind::Map;
        node.fields = {{"normal", numbers({0.2, -0.1, 1.0})}, {"radius", scalar("0.4")}, {"stiffness", scalar("1e5")}};
        spec.type = "sphere_plane";
        spec.params = mbd::Params("force 'touch'", &node);
        const mbd::contact::PlaneContact plane(spec, mbd::Dimension::Spatial, "circle_line");
        const mbd::Vec3 n = bi.A * mbd::Vec3(0.2, -0.1, 1.0).normalized();
        expect_gap_and_rate(plane, i, j, n.dot(C - P0) - 0.4);
    }
    {
        mbd::Param node = scalar("");
        node.kind = mbd::Param::Kind::Map;
        node.fields = {{"radii", numbers({0.3, 0.5})}, {"stiffness", scalar("1e5")}};
        spec.type = "sphere_sphere";
        spec.params = mbd::Params("force 'touch'", &node);
        const mbd::contact::SphereContact spheres(spec, mbd::Dimension::Spatial, "circle_circle");
        expect_gap_and_rate(spheres, i, j, (C - P0).norm() - 0.8);
    }
}

// ------------------------------------------------------------------ bad input
std::string with_type(std::string yaml, const std::string& from, const std::string& to) {
    return yaml.replace(yaml.find("type: " + from), 6 + from.size(), "type: " + to);
}

std::string error_of(const std::string& yaml) {
    try {
        mbd::test::scene(yaml, "contact.yaml");
    } catch (const std::exception& e) {
        return e.what();
    }
    return "";
}

TEST(Contact, BadInputIsNamedWithItsKey) {
    Ball b;
    const std::string good = drop_scene("sphere_plane", b, 0.2, ", damping: 10");
    ASSERT_EQ(error_of(good), "");
    auto with = [&](const std::string& from, const std::string& to) { return mbd::test::replaced(good, from, to); };
    const struct {
        std::string yaml, expected;
    } cases[] = {
        {with("radius: 0.1", "radius: -0.1"), "'radius' must be positive"},
        {with("stiffness: 1000000", "stiffness: 0"), "'stiffness' must be positive"},
        {with("stiffness: 1000000", "stiffness: -5"), "'stiffness' must be positive"},
        {with("exponent: 1.5", "exponent: 0"), "'exponent' must be positive"},
        {with("normal: [0, 0, 1], ", ""), "missing key 'normal'"},
        {with("normal: [0, 0, 1]", "normal: [0, 0, 0]"), "'normal' must not be the zero vector"},
        {with("normal: [0, 0, 1]", "normal: [0, 1]"), "'normal' must be a list of 3 numbers"},
        {with("damping: 10", "damping: -1"), "'damping' must not be negative"},
        {with("damping: 10", "restitution: 0.8"), "'restitution' needs 'impact_velocity'"},
        {with("damping: 10", "restitution: 1.5, impact_velocity: 1"), "'restitution' must be in (0, 1]"},
        {with("damping: 10", "damping: 1, restitution: 0.5, impact_velocity: 1"), "either 'damping' or 'restitution'"},
        {with("damping: 10", "restitution: 0.5, impact_velocity: 1, restitution_model: newton"),
         "'restitution_model' must be 'lankarani_nikravesh' or 'hunt_crossley'"},
        {with("damping: 10", "static_friction: 0.2, kinetic_friction: 0.3"), "must not exceed 'static_friction'"},
        {with("damping: 10", "static_friction: 0.2, stiction_velocity: 0"), "'stiction_velocity' must be positive"},
        {with("bodies: [ground, ball]", "bodies: [ground, ball], point: [0, 0, 0]"), "not a world 'point'"},
        {with("damping: 10", "damping: 10, radii: [1, 2]"), "unknown key 'radii'"},
        {drop_scene("sphere_sphere", b, 0.2, ""), "missing key 'radii'"},
    };
    for (const auto& c : cases) {
        const std::string error = error_of(c.yaml);
        EXPECT_NE(error.find(c.expected), std::string::npos) << c.expected << "\n got: " << error;
        EXPECT_NE(error.find("contact.yaml:"), std::string::npos) << error;  // file:line
        EXPECT_NE(error.find("force 'floor'"), std::string::npos) << error;
    }
    // a planar scene for a spatial type, and the other way round: refused naming the counterpart
    const std::string planar_sphere =
        with_type(drop_scene("circle_line", b, 0.2, ""), "circle_line", "sphere_plane");
    EXPECT_NE(error_of(planar_sphere).find("'sphere_plane' is a spatial contact; in a planar scene use 'circle_line'"),
              std::string::npos)
        << error_of(planar_sphere);
    const std::string spatial_circle = with_type(drop_scene("sphere_plane", b, 0.2, ""), "sphere_plane", "circle_line");
    EXPECT_NE(error_of(spatial_circle).find("'circle_line' is a planar contact; in a spatial scene use 'sphere_plane'"),
              std::string::npos)
        << error_of(spatial_circle);
    // sphere_sphere: a radius that is not positive, named with the body
    std::string two = collision_scene("sphere_sphere", "");
    two.replace(two.find("radii: [0.1, 0.1]"), 17, "radii: [0.1, -0.1]");
    EXPECT_NE(error_of(two).find("'radii' must be positive (the radius of body 'b''s sphere"), std::string::npos)
        << error_of(two);
}

}  // namespace
