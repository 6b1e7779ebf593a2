// The rolling_disc joint (plugins/joints/rolling_disc) and the velocity-level (nonholonomic) rows of
// the joint interface, against independent oracles: the closed-form steady circular rolling
// of a uniform thin disc, its contact force, the contact point's velocity computed from the
// state, the conservation of energy, and the refusals by name.
//
// Steady rolling in a circle (Neimark & Fufaev, Dynamics of Nonholonomic Systems, Ch. II;
// Greenwood, Advanced Dynamics, Sec. 4.7), derived from the Newton-Euler equations of the
// disc: mass m, radius r, axial moment I_a = m r^2 / 2, diametral I_d = m r^2 / 4, lean theta
// from the vertical Z, yaw rate Omega. With the horizontal unit vector h normal to the heading
// t = h x Z, the axle a = cos(theta) h + sin(theta) Z and the in-plane "up" u = cos(theta) Z -
// sin(theta) h (so a x u = t), the angular velocity is omega = Omega Z + psidot a, i.e.
// omega_a = Omega sin(theta) + psidot along a and omega_u = Omega cos(theta) along u. The
// contact point C = G - r u is at rest, so V_G = omega x (r u) = r omega_a t: the centre runs
// on a horizontal circle of radius R_G about O = G + R_G h when r omega_a = Omega R_G, with
// acceleration a_G = Omega Z x V_G = r omega_a Omega h. Newton: the contact force is
// F = m r omega_a Omega h + m g Z. Euler about G: the frame (a, u, t) turns at Omega Z, so
// dH/dt = Omega Z x (I_a omega_a a + I_d omega_u u) = Omega cos(theta) (I_d Omega sin(theta) -
// I_a omega_a) t, and the moment of F about G is (-r u) x F = m r (r omega_a Omega cos(theta) +
// g sin(theta)) t. Equating, with omega_a = Omega R_G / r:
//     Omega^2 cos(theta) (r sin(theta) / 4 - 3 R_G / 2) = g sin(theta).
#include <mbd/derivative_check.hpp>
#include <mbd/mobility.hpp>
#include <mbd/model_system.hpp>
#include <mbd/reactions.hpp>
#include <mbd/sdk/rotation.hpp>
#include <mbd/simulation.hpp>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "support/test_support.hpp"

namespace {

using mbd::Vec3;
using mbd::test::g17;
using mbd::test::shared_registry;

// The steady circle: r = 0.3 m, m = 2 kg, lean 0.3 rad, centre circle radius R_G = -1 m (the
// circle's centre on the side the disc leans to), g = 9.81.
struct SteadyCircle {
    double m = 2.0, r = 0.3, theta = 0.3, R_G = -1.0, g = 9.81;
    double Omega() const {
        return std::sqrt(g * std::sin(theta) / (std::cos(theta) * (r * std::sin(theta) / 4 - 1.5 * R_G)));
    }
    double omega_a() const { return Omega() * R_G / r; }
    double psidot() const { return omega_a() - Omega() * std::sin(theta); }
    double speed() const { return std::abs(r * omega_a()); }
    // At t = 0: contact at the origin, h = world y, heading t = h x Z = world x.
    Vec3 h(double t) const { return Eigen::AngleAxisd(Omega() * t, Vec3::UnitZ()) * Vec3::UnitY(); }
    Vec3 axle(double t) const { return std::cos(theta) * h(t) + std::sin(theta) * Vec3::UnitZ(); }
    Vec3 up(double t) const { return std::cos(theta) * Vec3::UnitZ() - std::sin(theta) * h(t); }
    Vec3 centre(double t) const {
        const Vec3 G0 = r * up(0.0), O = G0 + R_G * h(0.0);
        return O - R_G * h(t);
    }
    Vec3 omega(double t) const { return Omega() * Vec3::UnitZ() + psidot() * axle(t); }
    Vec3 contact_force(double t) const { return m * r * omega_a() * Omega() * h(t) + m * g * Vec3::UnitZ(); }

    std::string scene(const std::string& extra_joint_keys = "") const {
        const Vec3 G = centre(0.0), V = r * omega_a() * Vec3::UnitX(), w = omega(0.0), a = axle(0.0);
        auto v3 = [](const Vec3& x) { return "[" + g17(x.x()) + ", " + g17(x.y()) + ", " + g17(x.z()) + "]"; };
        const double Id = m * r * r / 4, Ia = m * r * r / 2;
        // body z = the axle: a rotation about world x by theta - pi/2 takes z to (0, cos, sin)
        return "name: rolling-disc\ndimension: spatial\ngravity: [0, 0, -" + g17(g) +
               "]\nbodies:\n  - name: disc\n    mass: " + g17(m) + "\n    inertia: [" + g17(Id) + ", " + g17(Id) +
               ", " + g17(Ia) + "]\n    position: " + v3(G) + "\n    orientation: {axis: [1, 0, 0], angle: " +
               g17(theta - M_PI / 2) + "}\n    velocity: " + v3(V) + "\n    angular_velocity: " + v3(w) +
               "\njoints:\n  - {name: contact, type: rolling_disc, bodies: [ground, disc], point: " + v3(G) +
               ", axis: " + v3(a) + ", radius: " + g17(r) + extra_joint_keys + "}\n";
    }
};

struct DiscState {
    Vec3 G, V, omega, axle;
};
DiscState disc_state(const mbd::State& s) {
    const mbd::Mat3 A = mbd::rotation_from_euler_parameters(s.q.segment<4>(3).normalized());
    return {s.q.head<3>(), s.v.head<3>(), A * s.v.segment<3>(3), A.col(2)};
}

// The velocity of the disc's material point at its lowest rim point, from the state alone.
Vec3 contact_velocity(const DiscState& d, double r) {
    const Vec3 down = -(Vec3::UnitZ() - d.axle.z() * d.axle).normalized();
    return d.V + d.omega.cross(r * down);
}

// The steady circle, started exactly on it, by each formulation that obeys velocity-level rows.
class SteadyCircleTest : public ::testing::TestWithParam<const char*> {};

TEST_P(SteadyCircleTest, KeepsLeanSpeedAndTurningRate) {
    const SteadyCircle c;
    const mbd::Model model = mbd::test::scene(c.scene());
    mbd::ModelSystem system(model);
    mbd::SimulationSettings settings;
    settings.formulation = GetParam();
    settings.integrator = "dopri5";
    settings.integration.tolerance = 1e-13;
    settings.t_end = 10.0;
    settings.output_step = 0.05;
    settings.progress = false;
    settings.messages = mbd::MessageLog::silent();
    settings.reactions = true;
    double lean = 0.0, speed = 0.0, turning = 0.0, centre = 0.0, slip = 0.0, energy = 0.0, force = 0.0;
    double E0 = 0.0;
    long samples = 0;
    mbd::simulate(model, shared_registry(), settings, [&](const mbd::SimulationSample& sample) {
        const mbd::State& s = sample.state;
        const DiscState d = disc_state(s);
        const double E = system.kinetic_energy(s) + system.potential_energy(s);
        if (samples++ == 0) E0 = E;
        energy = std::max(energy, std::abs(E - E0) / std::abs(E0));
        lean = std::max(lean, std::abs(std::asin(d.axle.z()) - c.theta));
        speed = std::max(speed, std::abs(d.V.norm() - c.speed()));
        // the axle's heading turns at Omega: dphi/dt of its horizontal projection, adot = omega x a
        const Vec3 adot = d.omega.cross(d.axle);
        const double phidot =
            (d.axle.x() * adot.y() - d.axle.y() * adot.x()) / (d.axle.x() * d.axle.x() + d.axle.y() * d.axle.y());
        turning = std::max(turning, std::abs(phidot - c.Omega()));
        centre = std::max(centre, (d.G - c.centre(s.t)).norm());
        slip = std::max(slip, contact_velocity(d, c.r).norm());
        // the contact's reaction on the disc (its no-slip and normal rows' multipliers)
        const auto reactions = mbd::joint_reactions(system, s, *sample.lambda);
        force = std::max(force, (reactions[0].on[1].force - c.contact_force(s.t)).norm() / c.contact_force(0).norm());
        return true;
    });
    std::printf("%s: steady circle, 10 s (Omega %.6f rad/s, speed %.6f m/s): |d lean| %.2e rad, |d speed| %.2e m/s, "
                "|d turning rate| %.2e rad/s, |d centre| %.2e m, |v_C| %.2e m/s, |dE|/E %.2e, |dF|/F %.2e\n",
                GetParam(), c.Omega(), c.speed(), lean, speed, turning, centre, slip, energy, force);
    EXPECT_EQ(samples, 201);
    EXPECT_LT(lean, 1e-8);
    EXPECT_LT(speed, 1e-8);
    EXPECT_LT(turning, 1e-8);
    EXPECT_LT(centre, 1e-7);  // the whole path, 14 m long, on the closed-form circle
    EXPECT_LT(slip, 1e-10);
    EXPECT_LT(energy, 1e-9);
    EXPECT_LT(force, 1e-8);
}

INSTANTIATE_TEST_SUITE_P(Formulations, SteadyCircleTest, ::testing::Values("augmented", "embedding"));

// The rows against their definitions at random states off the manifold: C is the height of the
// rim's lowest point above z = 0, and the velocity-level rows (J v + C_t in the stack with
// velocity rows) are the components of the contact point's velocity along the rolling
// direction a x Z / |a x Z| and the lateral direction Z x that.
TEST(RollingDisc, RowsAreTheContactHeightAndTheContactPointVelocity) {
    const SteadyCircle c;
    const mbd::Model model = mbd::test::scene(c.scene());
    mbd::ModelSystem system(model);
    ASSERT_EQ(system.constraint_rows(true), 1);
    ASSERT_EQ(system.velocity_constraint_rows(), 2);
    EXPECT_EQ(system.describe_row(1), "joint 'contact' (no-slip rolling direction)");
    std::mt19937 rng(17);
    for (int trial = 0; trial < 5; ++trial) {
        const mbd::State s = mbd::random_state(model, rng, 0.3, 3.0, 0.0);
        const DiscState d = disc_state(s);
        const Vec3 down = -(Vec3::UnitZ() - d.axle.z() * d.axle).normalized();
        const Vec3 rolling = d.axle.cross(Vec3::UnitZ()).normalized(), lateral = Vec3::UnitZ().cross(rolling);
        const Vec3 vC = contact_velocity(d, c.r);
        mbd::ConstraintValues cv;
        system.constraints_with_velocity_rows(s, cv, true);
        ASSERT_EQ(cv.J.rows(), 3);
        const Eigen::VectorXd rates = cv.J * s.v + cv.C_t;
        EXPECT_NEAR(cv.C[0], (d.G + c.r * down).z(), 1e-14);
        EXPECT_NEAR(rates[0], vC.z(), 1e-13);  // the height's rate: the normal component
        EXPECT_NEAR(rates[1], rolling.dot(vC), 1e-13);
        EXPECT_NEAR(rates[2], lateral.dot(vC), 1e-13);
        EXPECT_EQ(cv.C[1], 0.0);  // velocity-level rows restrict no position
        EXPECT_EQ(cv.C[2], 0.0);
        mbd::ConstraintValues holonomic;
        system.constraints(s, holonomic, true);
        EXPECT_EQ(holonomic.J.rows(), 1);
    }
}

// Off the steady circle (the spin cut by 40%: the disc wobbles, turns and falls further over),
// augmented and embedding (independent velocities from the null space of [J; A], 3 of 6) follow
// the same motion; neither slips.
// A thin disc on a plane: 6 velocities, 1 holonomic row (contact height) and 2 no-slip rows,
// so 5 freedoms of position and 3 of velocity (spin, lean rate, heading rate); mbd check says so.
TEST(RollingDisc, MobilityCountsTheFreedomsOfPositionAndOfVelocity) {
    const mbd::Model model = mbd::test::load("examples/spatial-rolling-disc.yaml");
    const mbd::MobilityReport m = mbd::analyse_mobility(model, model.initial_state());
    EXPECT_EQ(m.rank_dof, 5);
    EXPECT_EQ(m.velocity_rows, 2);
    EXPECT_EQ(m.velocity_dof, 3);
    const mbd::test::CommandResult r =
        mbd::test::run_mbd("check " + mbd::test::scene_path("examples/spatial-rolling-disc.yaml").string());
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("velocity constraints (nonholonomic): 2 rows; degrees of freedom of the velocities "
                            "(rank of [C_q; A]): 3"),
              std::string::npos)
        << r.out;
}

TEST(RollingDisc, AugmentedAndEmbeddingAgreeOffTheSteadyCircle) {
    SteadyCircle c;
    const mbd::Model model = mbd::test::scene(c.scene());
    mbd::ModelSystem system(model);
    mbd::State start = system.initial_state();
    start.v.tail<3>() *= 0.6;
    std::vector<mbd::State> runs[2];
    const char* formulations[] = {"augmented", "embedding"};
    for (int k = 0; k < 2; ++k) {
        mbd::SimulationSettings settings;
        settings.formulation = formulations[k];
        settings.integration.tolerance = 1e-11;
        settings.t_end = 1.5;
        settings.output_step = 0.1;
        settings.progress = false;
        settings.messages = mbd::MessageLog::silent();
        settings.initial_state = start;
        mbd::simulate(model, shared_registry(), settings, [&](const mbd::SimulationSample& sample) {
            runs[k].push_back(sample.state);
            return true;
        });
    }
    ASSERT_EQ(runs[0].size(), runs[1].size());
    double dq = 0.0, slip = 0.0, lean_change = 0.0;
    const double lean0 = std::asin(disc_state(runs[0].front()).axle.z());
    for (size_t i = 0; i < runs[0].size(); ++i) {
        dq = std::max(dq, mbd::test::position_difference(model, runs[0][i].q, runs[1][i].q));
        for (const auto& run : runs) slip = std::max(slip, contact_velocity(disc_state(run[i]), c.r).norm());
        lean_change = std::max(lean_change, std::abs(std::asin(disc_state(runs[0][i]).axle.z()) - lean0));
    }
    std::printf("off the steady circle, 1.5 s: augmented vs embedding |dq| %.2e, |v_C| %.2e, lean change %.3f rad\n",
                dq, slip, lean_change);
    EXPECT_GT(lean_change, 0.05);  // the motion is not the steady one
    EXPECT_LT(dq, 1e-8);
    EXPECT_LT(slip, 1e-10);
}

// The classical equations of the rolling disc in lean theta, heading psi and the axial rate
// omega_a (derived in the frame (t, a, u) of the SteadyCircle comment above, which turns at
// psidot Z + thetadot t; the disc at omega = thetadot t + omega_a a + psidot cos(theta) u;
// V_G = r omega_a t - r thetadot a), Newton-Euler with the contact force eliminated:
//   (I_d + m r^2) thetaddot = -I_d psidot^2 sin cos + (I_a + m r^2) psidot cos omega_a + m g r sin
//   (I_a + m r^2) omega_a'  = -m r^2 psidot cos thetadot
//   I_d cos psiddot         = 2 I_d psidot thetadot sin - I_a thetadot omega_a
// (steady, thetadot = 0, the first is the SteadyCircle's Omega relation), integrated here by
// RK4 at a step of 1/4000 s (its error, by halving the step, below 1e-11 in 1 s), with the
// mass centre's horizontal position from V_G.
struct DiscOde {
    double m = 2.0, r = 0.3, g = 9.81;
    using Y = Eigen::Matrix<double, 7, 1>;  // theta, thetadot, psi, psidot, omega_a, x_G, y_G
    Y rate(const Y& y) const {
        const double Id = m * r * r / 4, Ia = m * r * r / 2, s = std::sin(y[0]), c = std::cos(y[0]);
        const double thetadot = y[1], psi = y[2], psidot = y[3], wa = y[4];
        const Vec3 t(std::cos(psi), std::sin(psi), 0.0), h(-std::sin(psi), std::cos(psi), 0.0);
        const Vec3 a = c * h + s * Vec3::UnitZ();
        const Vec3 V = r * wa * t - r * thetadot * a;
        Y d;
        d << thetadot, (-Id * psidot * psidot * s * c + (Ia + m * r * r) * psidot * c * wa + m * g * r * s) / (Id + m * r * r),
            psidot, (2 * Id * psidot * thetadot * s - Ia * thetadot * wa) / (Id * c),
            -m * r * r * psidot * c * thetadot / (Ia + m * r * r), V.x(), V.y();
        return d;
    }
    Y integrate(Y y, double t_end, int steps) const {
        const double h = t_end / steps;
        for (int k = 0; k < steps; ++k) {
            const Y k1 = rate(y), k2 = rate(y + h / 2 * k1), k3 = rate(y + h / 2 * k2), k4 = rate(y + h * k3);
            y += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
        }
        return y;
    }
};

TEST(RollingDisc, LeanAndHeadingFollowTheClassicalDiscEquations) {
    // released at lean 0.2 rad, heading along x (axle in the y-z plane), turning at 2 rad/s and
    // rolling at r omega_a = -4.5 m/s: not the steady circle, so the lean falls to 0.083 rad and
    // rises again within the second
    const DiscOde ode;
    const double theta0 = 0.2, psidot0 = 2.0, wa0 = -15.0, r = ode.r;
    DiscOde::Y y0;
    y0 << theta0, 0.0, 0.0, psidot0, wa0, 0.0, -r * std::sin(theta0);
    const Vec3 a(0.0, std::cos(theta0), std::sin(theta0)), u(0.0, -std::sin(theta0), std::cos(theta0));
    const Vec3 G = r * u, V = r * wa0 * Vec3::UnitX(), w = wa0 * a + psidot0 * std::cos(theta0) * u;
    auto v3 = [](const Vec3& x) { return "[" + g17(x.x()) + ", " + g17(x.y()) + ", " + g17(x.z()) + "]"; };
    const double Id = ode.m * r * r / 4, Ia = ode.m * r * r / 2;
    const std::string yaml = "name: leaning disc\ndimension: spatial\ngravity: [0, 0, -" + g17(ode.g) +
                             "]\nbodies:\n  - {name: disc, mass: " + g17(ode.m) + ", inertia: [" + g17(Id) + ", " +
                             g17(Id) + ", " + g17(Ia) + "], position: " + v3(G) +
                             ", orientation: {axis: [1, 0, 0], angle: " + g17(theta0 - M_PI / 2) + "}, velocity: " + v3(V) +
                             ", angular_velocity: " + v3(w) + "}\njoints:\n  - {name: contact, type: rolling_disc, "
                             "bodies: [ground, disc], point: " + v3(G) + ", axis: " + v3(a) + ", radius: " + g17(r) + "}\n";
    const mbd::Model model = mbd::test::scene(yaml);
    for (const char* formulation : {"augmented", "embedding"}) {
        SCOPED_TRACE(formulation);
        double worst_lean = 0.0, worst_heading = 0.0, worst_centre = 0.0, lean_change = 0.0;
        mbd::simulate(model, shared_registry(), mbd::test::adaptive_run(formulation, "dop853", 1e-11, 1.0, 0.125),
                      [&](const mbd::SimulationSample& sample) {
                          const DiscState d = disc_state(sample.state);
                          const DiscOde::Y y = ode.integrate(y0, sample.state.t, static_cast<int>(4000 * sample.state.t));
                          const double lean = std::asin(d.axle.z());
                          const Vec3 h = Vec3(d.axle.x(), d.axle.y(), 0.0) / std::cos(lean);
                          const double heading = std::atan2(-h.x(), h.y());
                          worst_lean = std::max(worst_lean, std::abs(lean - y[0]));
                          worst_heading = std::max(worst_heading, std::abs(mbd::wrap_angle(heading - y[2])));
                          worst_centre = std::max(worst_centre, std::hypot(d.G.x() - y[5], d.G.y() - y[6]));
                          lean_change = std::max(lean_change, std::abs(lean - theta0));
                          return true;
                      });
        std::printf("%s: leaning disc, 1 s against the classical equations: |d lean| %.2e rad, |d heading| %.2e rad, "
                    "|d centre| %.2e m (lean changed by up to %.3f rad)\n",
                    formulation, worst_lean, worst_heading, worst_centre, lean_change);
        EXPECT_GT(lean_change, 0.1);
        EXPECT_LT(worst_lean, 1e-9);  // measured 1e-11 (augmented and embedding)
        EXPECT_LT(worst_heading, 1e-9);
        EXPECT_LT(worst_centre, 1e-9);
    }
}

// Refusals by name: a planar scene; the formulations and the integrator that do not obey
// velocity-level rows; the embedding's recursive path.
TEST(RollingDisc, RefusesWhatCannotHoldIt) {
    const std::string planar =
        "name: flat\ndimension: planar\nbodies:\n  - {name: wheel, mass: 1, inertia: 0.1, position: [0, 0.3]}\njoints:\n"
        "  - {name: roll, type: rolling_disc, bodies: [ground, wheel], radius: 0.3}\n";
    try {
        mbd::test::scene(planar, "flat.yaml");
        ADD_FAILURE() << "a rolling disc in a planar scene was accepted";
    } catch (const mbd::InputError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("flat.yaml:6"), std::string::npos) << m;
        EXPECT_NE(m.find("joint 'roll': rolling_disc is a spatial joint"), std::string::npos) << m;
    }
    const std::string flat_disc =
        "name: lying\ndimension: spatial\nbodies:\n  - {name: disc, mass: 1, inertia: [0.25, 0.25, 0.5], "
        "position: [0, 0, 0.1]}\njoints:\n  - {name: roll, type: rolling_disc, bodies: [ground, disc], axis: [0, 0, 1], "
        "radius: 0.5}\n";
    try {
        mbd::test::scene(flat_disc, "lying.yaml");
        ADD_FAILURE() << "a disc lying flat was accepted";
    } catch (const mbd::InputError& e) {
        EXPECT_NE(std::string(e.what()).find("the wheel axis is along the plane normal"), std::string::npos) << e.what();
    }
    const SteadyCircle c;
    const mbd::Model model = mbd::test::scene(c.scene(), "disc.yaml");
    auto refusal = [&](const std::string& formulation, const std::string& integrator) {
        mbd::SimulationSettings settings;
        settings.formulation = formulation;
        settings.integrator = integrator;
        settings.integration.step = integrator == "generalized_alpha" ? 1e-3 : 0.0;
        settings.t_end = 0.01;
        settings.progress = false;
        settings.messages = mbd::MessageLog::silent();
        try {
            mbd::simulate(model, shared_registry(), settings);
        } catch (const mbd::InputError& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    for (const char* formulation : {"amalgamated", "hamiltonian"}) {
        const std::string m = refusal(formulation, "dopri5");
        EXPECT_NE(m.find("disc.yaml:"), std::string::npos) << m;
        EXPECT_NE(m.find("joint 'contact' (type rolling_disc) has 2 velocity-level (nonholonomic) constraint row(s), "
                         "which the '" + std::string(formulation) + "' formulation does not handle; use the augmented "
                         "or the embedding formulation"),
                  std::string::npos)
            << m;
    }
    const std::string alpha = refusal("augmented", "generalized_alpha");
    EXPECT_NE(alpha.find("which the generalized_alpha integrator does not handle"), std::string::npos) << alpha;
    const mbd::Model recursive = mbd::test::scene(c.scene() + "formulation: {type: embedding, path: recursive}\n");
    mbd::SimulationSettings settings;
    settings.t_end = 0.01;
    settings.progress = false;
    settings.messages = mbd::MessageLog::silent();
    try {
        mbd::simulate(recursive, shared_registry(), settings);
        ADD_FAILURE() << "the recursive path accepted a rolling disc";
    } catch (const mbd::InputError& e) {
        EXPECT_NE(std::string(e.what()).find("path: recursive: joint 'contact' (rolling_disc) has velocity-level"),
                  std::string::npos)
            << e.what();
    }
}

// The analyses built on the position constraints alone refuse the example scene by name, with
// its file:line and a non-zero exit; mbd modes refuses its steady circle as not steady.
TEST(RollingDisc, HolonomicAnalysesRefuseByName) {
    const std::string scene = mbd::test::scene_path("examples/spatial-rolling-disc.yaml").string();
    const std::string out = mbd::test::scratch("rolling-disc-refusals").string();
    const std::pair<std::string, std::string> cases[] = {
        {"statics " + scene, "the statics analysis"},
        {"kinematics " + scene + " --t-end 1 --step 0.1 --output " + out + "/k.csv", "the kinematic analysis"},
        {"inverse " + scene + " --t-end 1 --step 0.1 --output " + out + "/i.csv", "inverse dynamics"}};
    for (const auto& [arguments, analysis] : cases) {
        const auto r = mbd::test::run_mbd(arguments);
        EXPECT_NE(r.exit_code, 0) << arguments;
        EXPECT_NE(r.err.find("spatial-rolling-disc.yaml:19: joint 'contact' (type rolling_disc) has 2 velocity-level "
                             "(nonholonomic) constraint row(s), which " + analysis + " does not handle"),
                  std::string::npos)
            << r.err;
    }
    EXPECT_FALSE(std::filesystem::exists(out + "/k.csv"));
    // mbd modes handles the no-slip rows (tests/test_bicycle.cpp), but a disc rolling in a circle
    // is not a steady motion of uniform translations and fixed-axis turns: refused with its residual
    const auto r = mbd::test::run_mbd("modes " + scene + " --about initial");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find("is not an equilibrium or steady motion: the accelerations are"), std::string::npos) << r.err;
}

}  // namespace
