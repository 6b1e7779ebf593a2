// Contact between collision shapes found by FCL (issue 39; plugins/forces/collision_contact):
// the `collision:` key of bodies and the ground, against independent oracles:
//  - a sphere dropped on a plane rebounds, bounce after bounce, to e_k^2 h_k, with e_k the
//    restitution of the Hunt-Crossley law at that impact's speed from its exact energy balance
//    (below), not from the Lankarani-Nikravesh fit that sets the damping;
//  - a box on an incline steeper than atan(mu) slides at g (sin a - mu cos a); on a shallower one
//    it sticks; a sphere rolls down an incline at (5/7) g sin a;
//  - a box resting on a plane carries its weight on its 4 corners, equally; a capsule on both caps;
//  - the same sphere on a plane computed by the sphere_plane element and by the collision
//    contact agrees to 1e-10;
//  - two free bodies colliding conserve linear and angular momentum;
//  - the energy of a pile of 100 spheres never increases (every output row);
//  - a cylinder rolling on its side keeps its energy within the friction law's dissipation;
//  - bad input named by its body.
#include "support/force_element_states.hpp"
#include "support/test_support.hpp"

#include <mbd/simulation.hpp>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <functional>
#include <sstream>
#include <random>
#include <string>
#include <vector>

namespace {

using mbd::test::element;
using mbd::test::ElementStates;
using mbd::test::g17;

constexpr double kG = 9.81;

mbd::SimulationResult run(const mbd::Model& model, const std::string& integrator, double t_end, double tolerance,
                          double output_step, const std::function<void(const mbd::State&)>& sample = nullptr) {
    mbd::SimulationSettings s;
    s.formulation = "augmented";
    s.integrator = integrator;
    s.integration.tolerance = tolerance;
    s.t_end = t_end;
    s.output_step = output_step;
    s.progress = false;
    s.messages = mbd::MessageLog::silent();
    return mbd::simulate(model, mbd::test::shared_registry(), s, [&](const mbd::SimulationSample& x) {
        if (sample) sample(x.state);
        return true;
    });
}

// ------------------------------------------------------------------ the restitution oracle
// The Hunt-Crossley law F = k d^n (1 + alpha d'), alpha = c / k, on a mass m against a rigid
// plane without gravity: m v dv/dd = -k d^n (1 + alpha v) integrates in closed form, and the
// energy balance of approach (v_i -> 0) and rebound (0 -> -v_o) gives, for x = alpha v_i and
// y = alpha v_o,  x - ln(1 + x) = -y - ln(1 - y), whatever k, n and m: e = y / x.
double hunt_crossley_restitution(double alpha, double impact_speed) {
    const double x = alpha * impact_speed;
    const double target = x - std::log1p(x);
    double lo = 0.0, hi = 1.0;  // -y - ln(1 - y) rises from 0 to infinity on [0, 1)
    for (int k = 0; k < 200; ++k) {
        const double y = 0.5 * (lo + hi);
        (-y - std::log1p(-y) < target ? lo : hi) = y;
    }
    return 0.5 * (lo + hi) / x;
}

std::string ball_scene(double k, double e, double impact_speed, double height, const std::string& extra = "") {
    return "dimension: spatial\ngravity: [0, 0, -9.81]\n"
           "ground:\n  collision:\n    - {shape: plane, normal: [0, 0, 1]}\n"
           "bodies:\n  - name: ball\n    mass: 1\n    inertia: [0.004, 0.004, 0.004]\n"
           "    position: [0, 0, " + g17(height + 0.1) + "]\n" + extra +
           "    collision:\n      - shape: sphere\n        radius: 0.1\n"
           "        material: {stiffness: " + g17(k) + ", exponent: 1.5, restitution: " + g17(e) +
           ", impact_velocity: " + g17(impact_speed) + "}\n";
}

TEST(CollisionContact, SphereDroppedOnAPlaneReboundsToTheLawsRestitutionSquaredEachBounce) {
    const double h0 = 1.0, e = 0.8, k = 1e11, r = 0.1;
    const double v0 = std::sqrt(2 * kG * h0);
    const double alpha = 3.0 * (1.0 - e * e) / (4.0 * v0);  // Lankarani-Nikravesh: c = 3 k (1 - e^2) / (4 v_i)
    const mbd::Model model = mbd::test::scene(ball_scene(k, e, v0, h0));
    // the height the ball's bottom reaches in each flight: z - r + vz^2 / (2 g), constant in flight
    // (a bounce is the first sample in flight rising after one falling; samples in contact skipped)
    std::vector<double> apexes;
    bool falling = false;
    run(model, "dopri5", 2.2, 1e-12, 1e-3, [&](const mbd::State& s) {
        const double above = s.q[2] - r;
        if (above <= 0.0) return;
        if (falling && s.v[2] > 0.0) apexes.push_back(above + s.v[2] * s.v[2] / (2 * kG));
        falling = s.v[2] < 0.0;
    });
    ASSERT_GE(apexes.size(), 3u);
    double h = h0;
    for (size_t b = 0; b < 3; ++b) {
        const double e_b = hunt_crossley_restitution(alpha, std::sqrt(2 * kG * h));
        const double expected = e_b * e_b * h;
        EXPECT_NEAR(apexes[b], expected, 1e-4) << "bounce " << b + 1 << " (e = " << e_b << ")";
        ::testing::Test::RecordProperty("bounce" + std::to_string(b + 1) + "_height_error", g17(apexes[b] - expected));
        h = apexes[b];
    }
    // the first bounce, at the impact speed the damping was fitted to: Lankarani-Nikravesh's
    // approximate fit gives e_eff > e (0.833 for e = 0.8), which this oracle must see
    EXPECT_GT(apexes[0], e * e * h0 + 0.02);
}

// ------------------------------------------------------------------ friction on an incline
// The ground plane through the origin with normal n = (sin a, 0, cos a): downhill is
// d = (cos a, 0, -sin a). A body's axes are turned about y by a, so its z axis is n.
struct Incline {
    double a;
    Eigen::Vector3d n() const { return {std::sin(a), 0.0, std::cos(a)}; }
    Eigen::Vector3d down() const { return {std::cos(a), 0.0, -std::sin(a)}; }
    std::string ground(const std::string& material) const {
        return "dimension: spatial\ngravity: [0, 0, -9.81]\nground:\n  collision:\n    - {shape: plane, normal: [" +
               g17(n().x()) + ", 0, " + g17(n().z()) + "], material: " + material + "}\n";
    }
    std::string orientation() const { return "{axis: [0, 1, 0], angle: " + g17(a) + "}"; }
    std::string at(double height) const {
        const Eigen::Vector3d p = height * n();
        return "[" + g17(p.x()) + ", " + g17(p.y()) + ", " + g17(p.z()) + "]";
    }
};

// A 1 kg box, 0.2 x 0.2 x 0.1 m, on the incline at its static penetration (4 corners, Hertz law)
std::string box_on_incline(const Incline& incline, double mu_s, double mu_k, double stiction) {
    const double k = 1e8, m = 1.0;
    const double depth = std::pow(m * kG * std::cos(incline.a) / (4 * k), 1.0 / 1.5);
    return incline.ground("{static_friction: 1}") +
           "bodies:\n  - name: box\n    mass: 1\n    inertia: [0.004166666666666667, 0.004166666666666667, "
           "0.006666666666666667]\n    position: " + incline.at(0.05 - depth) +
           "\n    orientation: " + incline.orientation() +
           "\n    collision:\n      - shape: box\n        size: [0.2, 0.2, 0.1]\n"
           "        material: {stiffness: " + g17(k) + ", restitution: 0.5, impact_velocity: 1, static_friction: " +
           g17(mu_s) + ", kinetic_friction: " + g17(mu_k) + ", stiction_velocity: " + g17(stiction) + "}\n";
}

double speed_along(const mbd::State& s, const Eigen::Vector3d& d) { return d.dot(s.v.head<3>()); }

TEST(CollisionContact, BoxOnAnInclineSteeperThanTheFrictionAngleSlidesAtTheCoulombAcceleration) {
    const Incline incline{25.0 * M_PI / 180.0};
    const double mu_s = 0.3, mu_k = 0.2;
    ASSERT_GT(std::tan(incline.a), mu_s);
    const mbd::Model model = mbd::test::scene(box_on_incline(incline, mu_s, mu_k, 1e-4));
    std::vector<mbd::State> states;
    run(model, "dopri5", 1.0, 1e-10, 0.25, [&](const mbd::State& s) { states.push_back(s); });
    ASSERT_EQ(states.size(), 5u);
    const double expected = kG * (std::sin(incline.a) - mu_k * std::cos(incline.a));
    const double measured = (speed_along(states[4], incline.down()) - speed_along(states[2], incline.down())) / 0.5;
    EXPECT_NEAR(measured, expected, 1e-5 * expected);
    RecordProperty("relative_error", g17(measured / expected - 1));
    EXPECT_NEAR(states[4].q.segment<3>(0).dot(incline.n()), states[0].q.segment<3>(0).dot(incline.n()), 1e-6);
}

TEST(CollisionContact, BoxOnAnInclineShallowerThanTheFrictionAngleSticks) {
    const Incline incline{10.0 * M_PI / 180.0};
    const double mu_s = 0.3;
    ASSERT_LT(std::tan(incline.a), mu_s);
    const mbd::Model model = mbd::test::scene(box_on_incline(incline, mu_s, 0.2, 1e-7));
    std::vector<mbd::State> states;
    run(model, "cvode", 2.0, 1e-10, 0.5, [&](const mbd::State& s) { states.push_back(s); });
    ASSERT_EQ(states.size(), 5u);
    const double drift = (states.back().q.head<3>() - states.front().q.head<3>()).norm();
    EXPECT_LT(drift, 1e-6);
    RecordProperty("drift", g17(drift));
}

TEST(CollisionContact, SphereRollsDownAnInclineAtFiveSeventhsOfGSinA) {
    const Incline incline{20.0 * M_PI / 180.0};
    const double k = 1e8, r = 0.1;
    const double depth = std::pow(kG * std::cos(incline.a) / k, 1.0 / 1.5);
    const std::string scene = incline.ground("{static_friction: 1}") +
                              "bodies:\n  - name: ball\n    mass: 1\n    inertia: [0.004, 0.004, 0.004]\n"
                              "    position: " + incline.at(r - depth) +
                              "\n    collision:\n      - shape: sphere\n        radius: 0.1\n"
                              "        material: {stiffness: 1e8, restitution: 0.5, impact_velocity: 1, "
                              "static_friction: 0.5, stiction_velocity: 1e-4}\n";
    const mbd::Model model = mbd::test::scene(scene);
    std::vector<mbd::State> states;
    run(model, "dopri5", 0.6, 1e-10, 0.2, [&](const mbd::State& s) { states.push_back(s); });
    ASSERT_EQ(states.size(), 4u);
    // Rolling on a compliant contact, the ball turns about the contact point X, r - depth below its
    // centre: m a = m g sin a - F, I a / (r - depth) = F (r - depth), so
    // a = g sin a / (1 + I / (m (r - depth)^2)); the rigid limit (depth -> 0) is (5/7) g sin a.
    const double rolling_radius = r - depth;
    const double compliant = kG * std::sin(incline.a) / (1.0 + 0.004 / (rolling_radius * rolling_radius));
    const double rigid = 5.0 / 7.0 * kG * std::sin(incline.a);
    const double measured = (speed_along(states[3], incline.down()) - speed_along(states[1], incline.down())) / 0.4;
    EXPECT_NEAR(measured, compliant, 1e-6 * compliant);
    EXPECT_NEAR(measured, rigid, 3.0 * depth / r * rigid);  // 1.2e-4 here
    RecordProperty("relative_error_compliant", g17(measured / compliant - 1));
    RecordProperty("relative_error_rigid", g17(measured / rigid - 1));
    (void)k;
}

// A solid cylinder lying on its side rolls down the incline: held along its length (one contact
// at each end face's lowest rim point, each carrying half its weight), it accelerates at
// g sin a / (1 + I / (m (r - depth)^2)) (the rigid limit (2/3) g sin a) without turning about the
// normal or tipping, and its energy (kinetic, gravity's, the contacts' elastic) falls by no more
// than the regularized friction can dissipate while sticking: slip below the stiction velocity
// v_s under a friction force below mu_s N, so at most mu_s m g cos a v_s t.
TEST(CollisionContact, CylinderRollingOnItsSideKeepsItsEnergyWithinTheFrictionsDissipation) {
    const Incline incline{15.0 * M_PI / 180.0};
    const double k = 1e8, n = 1.5, r = 0.1, m = 1.0, mu_s = 0.5, v_s = 1e-4, t_end = 0.6;
    const double I_axis = 0.5 * m * r * r, I_across = m * (3 * r * r + 0.2 * 0.2) / 12.0;
    const double depth = std::pow(m * kG * std::cos(incline.a) / (2 * k), 1.0 / n);
    // the cylinder's axis (its shape's z) along the body's y: across the slope
    const std::string scene = incline.ground("{static_friction: 1}") +
                              "bodies:\n  - name: roller\n    mass: 1\n    inertia: [" + g17(I_across) + ", " +
                              g17(I_axis) + ", " + g17(I_across) + "]\n    position: " + incline.at(r - depth) +
                              "\n    orientation: " + incline.orientation() +
                              "\n    collision:\n      - shape: cylinder\n        radius: 0.1\n        length: 0.2\n"
                              "        orientation: {axis: [1, 0, 0], angle: 1.5707963267948966}\n"
                              "        material: {stiffness: 1e8, restitution: 0.5, impact_velocity: 1, "
                              "static_friction: 0.5, stiction_velocity: 1e-4}\n";
    const mbd::Model model = mbd::test::scene(scene);
    const mbd::ForceInstance& contact = element(model, "collision_contact");
    auto energy = [&](const mbd::State& s) {
        const Eigen::Vector3d w = s.v.segment<3>(3);
        ElementStates states(contact, s);
        return 0.5 * m * s.v.head<3>().squaredNorm() + 0.5 * w.dot(model.bodies[0].inertia * w) +
               m * kG * s.q[2] + contact.force->potential_energy(states.view);
    };
    std::vector<mbd::State> states;
    std::vector<double> E;
    run(model, "dopri5", t_end, 1e-10, 0.2, [&](const mbd::State& s) {
        states.push_back(s);
        E.push_back(energy(s));
    });
    ASSERT_EQ(states.size(), 4u);
    const double rolling_radius = r - depth;
    const double compliant = kG * std::sin(incline.a) / (1.0 + I_axis / (m * rolling_radius * rolling_radius));
    const double measured = (speed_along(states[3], incline.down()) - speed_along(states[1], incline.down())) / 0.4;
    EXPECT_NEAR(measured, compliant, 1e-6 * compliant);
    EXPECT_NEAR(measured, 2.0 / 3.0 * kG * std::sin(incline.a), 3.0 * depth / r * compliant);
    // it rolls about its own axis only (no yaw, no tipping onto one end), slipping slower than the
    // stiction velocity
    const Eigen::Vector3d w = states[3].v.segment<3>(3);
    const double slip = speed_along(states[3], incline.down()) - w.y() * rolling_radius;
    EXPECT_LT(std::abs(slip), v_s);
    EXPECT_LT(std::hypot(w.x(), w.z()), 1e-9);
    const double bound = mu_s * m * kG * std::cos(incline.a) * v_s * t_end;
    for (size_t k = 1; k < E.size(); ++k) {
        EXPECT_LE(E[k], E[k - 1] + 1e-9) << "row " << k;
        EXPECT_GE(E[k], E.front() - bound) << "row " << k;
    }
    RecordProperty("relative_error_compliant", g17(measured / compliant - 1));
    RecordProperty("energy_lost", g17(E.front() - E.back()));
    RecordProperty("friction_bound", g17(bound));
    RecordProperty("slip", g17(slip));
}

// ------------------------------------------------------------------ a box at rest
// Dropped slightly tilted, a 2 kg box settles level on its 4 corners at the penetration where
// 4 k d^n = m g (each corner a quarter of the weight): one contact point (FCL's own box/plane
// result, the deepest corner) could not hold it level. At rest its contacts carry its weight.
TEST(CollisionContact, BoxAtRestOnAPlaneCarriesItsWeightEquallyOnItsFourCorners) {
    const double m = 2.0, k = 1e8, n = 1.5, height = 0.1;
    const std::string scene =
        "dimension: spatial\ngravity: [0, 0, -9.81]\n"
        "ground:\n  collision:\n    - {shape: plane, normal: [0, 0, 1], material: {static_friction: 1}}\n"
        "bodies:\n  - name: box\n    mass: 2\n    inertia: [0.008333333333333333, 0.02833333333333333, "
        "0.03333333333333333]\n    position: [0.3, -0.2, 0.0502]\n    orientation: {axis: [1, 2, 0], angle: 0.002}\n"
        "    collision:\n      - shape: box\n        size: [0.4, 0.2, 0.1]\n"
        "        material: {stiffness: 1e8, exponent: 1.5, damping: 6e9, static_friction: 0.5, "
        "stiction_velocity: 1e-4}\n";
    const mbd::Model model = mbd::test::scene(scene);
    const auto result = run(model, "cvode", 3.0, 1e-10, 1.0);
    const mbd::State& s = result.final_state;
    const double depth = std::pow(m * kG / (4 * k), 1.0 / n);
    EXPECT_NEAR(s.q[2], 0.5 * height - depth, 1e-9);
    // level (a turn about the vertical, from friction while it settled, leaves the corners equal)
    const Eigen::Vector3d up = mbd::rotation_from_euler_parameters(s.q.segment<4>(3)).col(2);
    EXPECT_LT(std::hypot(up.x(), up.y()), 1e-8) << "the box is level: its corners carry equal loads";
    const mbd::ForceInstance& f = element(model, "collision_contact");
    ElementStates states(f, s);
    Eigen::VectorXd Q = Eigen::VectorXd::Zero(12);
    f.force->evaluate(states.view, Q);
    EXPECT_NEAR(Q[6 + 2], m * kG, 1e-8 * m * kG);      // the box's contacts carry its weight
    EXPECT_NEAR(Q.segment<2>(6).norm(), 0.0, 1e-8);     // and nothing sideways
    EXPECT_NEAR(Q.segment<3>(9).norm(), 0.0, 1e-8);     // nor a moment: the corners share it equally
    RecordProperty("height_error", g17(s.q[2] - (0.5 * height - depth)));
    RecordProperty("weight_error", g17(Q[6 + 2] - m * kG));
    RecordProperty("moment", g17(Q.segment<3>(9).norm()));
}

// A capsule lying on a plane, off-centre in its body, at the depth where its two end caps
// each carry half its weight, k d^n = m g / 2: its contacts carry exactly its weight at the
// caps' feet (no moment about its mass centre from the symmetric pair), and tilted about its
// axis' normal, the lower cap alone pushes, harder.
TEST(CollisionContact, CapsuleLyingOnAPlaneRestsOnBothEndCaps) {
    const double m = 2.0, k = 1e8, n = 1.5, r = 0.05, length = 0.4;
    const mbd::Model model = mbd::test::scene(
        "dimension: spatial\ngravity: [0, 0, -9.81]\nground:\n  collision:\n    - {shape: plane}\n"
        "bodies:\n  - name: rod\n    mass: 2\n    inertia: [0.002, 0.03, 0.03]\n    collision:\n"
        "      - {shape: capsule, radius: 0.05, length: 0.4, orientation: {axis: [0, 1, 0], angle: "
        "1.5707963267948966}, material: {stiffness: 1e8, exponent: 1.5}}\n");
    const mbd::ForceInstance& f = element(model, "collision_contact");
    const double depth = std::pow(m * kG / (2 * k), 1.0 / n);
    mbd::State s;
    s.q.resize(7);
    s.v = Eigen::VectorXd::Zero(6);
    s.q << 0.3, -0.2, r - depth, 1, 0, 0, 0;
    Eigen::VectorXd Q = Eigen::VectorXd::Zero(12);
    ElementStates level(f, s);
    f.force->evaluate(level.view, Q);
    EXPECT_NEAR(Q[6 + 2], m * kG, 1e-12 * m * kG);
    EXPECT_NEAR(Q.segment<2>(6).norm(), 0.0, 1e-12);
    EXPECT_NEAR(Q.segment<3>(9).norm(), 0.0, 1e-12 * m * kG * length);
    // raise one end: the other cap, now 2 mm deeper at its centre's foot, pushes alone with k d^n
    const double tilt = 0.01;  // rad about y: the cap at x = -L/2 goes down by L/2 sin(tilt)
    const Eigen::Quaterniond e(Eigen::AngleAxisd(tilt, Eigen::Vector3d::UnitY()));
    s.q.segment<4>(3) << e.w(), e.x(), e.y(), e.z();
    Q.setZero();
    ElementStates tilted(f, s);
    f.force->evaluate(tilted.view, Q);
    const double lower = r - depth - 0.5 * length * std::sin(tilt);  // the lower cap centre's height
    EXPECT_NEAR(Q[6 + 2], k * std::pow(r - lower, n), 1e-12 * Q[6 + 2]);
}

// ------------------------------------------------------------------ against sphere_plane
// The same sphere on the same plane, as the two-body sphere_plane element and as collision
// shapes, with friction: the generalized forces on the ball at random overlapping states agree.
TEST(CollisionContact, SpherePlaneElementAndCollisionContactGiveTheSameForce) {
    const std::string law = "stiffness: 1e7, exponent: 1.5, restitution: 0.7, impact_velocity: 2, "
                            "static_friction: 0.4, kinetic_friction: 0.3, stiction_velocity: 0.01";
    const std::string bodies = "bodies:\n  - name: ball\n    mass: 1\n    inertia: [0.004, 0.004, 0.004]\n"
                               "    position: [0, 0, 0.1]\n";
    const mbd::Model by_element = mbd::test::scene(
        "dimension: spatial\n" + bodies +
        "forces:\n  - {type: sphere_plane, bodies: [ground, ball], normal: [0, 0.6, 0.8], radius: 0.1, " + law + "}\n");
    const mbd::Model by_collision = mbd::test::scene(
        "dimension: spatial\nground:\n  collision:\n    - {shape: plane, normal: [0, 0.6, 0.8], material: "
        "{static_friction: 0.4, kinetic_friction: 0.3, stiction_velocity: 0.01}}\n" + bodies +
        "    collision:\n      - {shape: sphere, radius: 0.1, material: {" + law + "}}\n");
    const mbd::ForceInstance& a = element(by_element, "sphere_plane");
    const mbd::ForceInstance& b = element(by_collision, "collision_contact");
    std::mt19937 rng(39);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int touching = 0;
    double worst = 0.0;
    for (int trial = 0; trial < 200; ++trial) {
        mbd::State s;
        s.q.resize(7);
        s.v.resize(6);
        const Eigen::Vector3d n(0, 0.6, 0.8);
        const Eigen::Vector3d lateral(u(rng), u(rng), u(rng));
        s.q.head<3>() = (0.1 - 0.002 * (1 + u(rng))) * n + (lateral - lateral.dot(n) * n);
        s.q.segment<4>(3) = Eigen::Vector4d(u(rng), u(rng), u(rng), u(rng)).normalized();
        for (int k = 0; k < 6; ++k) s.v[k] = (trial % 3 == 0 ? 1e-3 : 1.0) * u(rng);  // stuck and sliding
        ElementStates sa(a, s), sb(b, s);
        Eigen::VectorXd Qa = Eigen::VectorXd::Zero(12), Qb = Eigen::VectorXd::Zero(12);
        a.force->evaluate(sa.view, Qa);
        b.force->evaluate(sb.view, Qb);
        if (Qa.tail<6>().norm() > 0) ++touching;
        if (Qa.tail<6>().norm() > 0) worst = std::max(worst, (Qa.tail<6>() - Qb.tail<6>()).norm() / Qa.tail<6>().norm());
        EXPECT_LE((Qa.tail<6>() - Qb.tail<6>()).norm(), 1e-10 * Qa.tail<6>().norm()) << "trial " << trial;
    }
    EXPECT_GT(touching, 150);
    RecordProperty("worst_relative_difference", g17(worst));
}

// ------------------------------------------------------------------ momentum
struct Momenta {
    Eigen::Vector3d linear = Eigen::Vector3d::Zero(), angular = Eigen::Vector3d::Zero();
};
Momenta momenta(const mbd::Model& model, const mbd::State& s) {
    Momenta out;
    for (int b = 0; b < model.body_count(); ++b) {
        const double m = model.bodies[b].mass;
        const Eigen::Vector3d R = s.q.segment<3>(7 * b), Rdot = s.v.segment<3>(6 * b);
        const Eigen::Matrix3d A = mbd::rotation_from_euler_parameters(s.q.segment<4>(7 * b + 3));
        out.linear += m * Rdot;
        out.angular += R.cross(m * Rdot) + A * (model.bodies[b].inertia * s.v.segment<3>(6 * b + 3));
    }
    return out;
}

// A box hit off-centre by a spinning capsule (a pair FCL solves by GJK/EPA), then by a sphere
// (analytic), with friction, no gravity: every contact force acts equal and opposite at one point.
TEST(CollisionContact, TwoFreeBodiesCollidingConserveLinearAndAngularMomentum) {
    const std::string material = "{stiffness: 1e6, exponent: 1.5, restitution: 0.6, impact_velocity: 2, "
                                 "static_friction: 0.5, kinetic_friction: 0.4, stiction_velocity: 1e-3}";
    const std::string scene =
        "dimension: spatial\nbodies:\n"
        "  - name: box\n    mass: 2\n    inertia: [0.02, 0.03, 0.04]\n    position: [0, 0, 0]\n"
        "    collision:\n      - {shape: box, size: [0.3, 0.4, 0.5], material: " + material + "}\n"
        "  - name: capsule\n    mass: 1\n    inertia: [0.01, 0.01, 0.002]\n    position: [-0.45, 0.1, 0.12]\n"
        "    orientation: {axis: [1, 1, 0], angle: 0.7}\n    velocity: [2, 0.1, 0]\n"
        "    angular_velocity: [0, 3, 5]\n"
        "    collision:\n      - {shape: capsule, radius: 0.05, length: 0.3, material: " + material + "}\n"
        "  - name: ball\n    mass: 0.5\n    inertia: [0.002, 0.002, 0.002]\n    position: [0.1, 0.6, -0.1]\n"
        "    velocity: [0, -2, 0.3]\n    angular_velocity: [4, 0, 0]\n"
        "    collision:\n      - {shape: sphere, radius: 0.1, material: " + material + "}\n";
    const mbd::Model model = mbd::test::scene(scene);
    std::vector<mbd::State> states;
    run(model, "dopri5", 0.5, 1e-11, 0.05, [&](const mbd::State& s) { states.push_back(s); });
    const Momenta start = momenta(model, states.front()), end = momenta(model, states.back());
    EXPECT_LE((end.linear - start.linear).norm(), 1e-12 * start.linear.norm());
    EXPECT_LE((end.angular - start.angular).norm(), 1e-9 * start.angular.norm());
    RecordProperty("linear_relative", g17((end.linear - start.linear).norm() / start.linear.norm()));
    RecordProperty("angular_relative", g17((end.angular - start.angular).norm() / start.angular.norm()));
    // the bodies did collide: the box, at rest before, moves
    EXPECT_GT(states.back().v.head<3>().norm(), 0.1);
}

// ------------------------------------------------------------------ a pile
// Spheres dropped in a heap onto the ground, bouncing off it and each other with restitution
// below 1 and friction: the energy (kinetic, gravity's and the contacts' elastic energy) never
// rises from one output row to the next, beyond the integrator's tolerance.
TEST(CollisionContact, EnergyNeverIncreasesInAPileOfSpheres) {
    const int count = 100, side = 5;
    // soft enough (2 mm of a 50 mm radius under a sphere's weight) for a short test: its cost is
    // the steps at the contacts' onsets, where the force's second derivative is infinite
    const double k = 1e4, tolerance = 1e-7, t_end = 0.3;
    std::ostringstream scene;
    scene << "dimension: spatial\ngravity: [0, 0, -9.81]\nground:\n  collision:\n"
             "    - {shape: plane, normal: [0, 0, 1], material: {static_friction: 0.3}}\nbodies:\n";
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> jitter(-0.02, 0.02);
    for (int b = 0; b < count; ++b) {
        // 4 layers of side x side spheres, each 0.12 m from its neighbours (0.11 m between layers), jittered
        const double x = 0.12 * (b % side) + jitter(rng), y = 0.12 * ((b / side) % side) + jitter(rng);
        const double z = 0.08 + 0.11 * (b / (side * side));
        scene << "  - name: s" << b << "\n    mass: 0.1\n    inertia: [1e-4, 1e-4, 1e-4]\n    position: ["
              << g17(x) << ", " << g17(y) << ", " << g17(z) << "]\n"
              << "    collision:\n      - {shape: sphere, radius: 0.05, material: {stiffness: " << g17(k) << ", restitution: 0.5, "
                 "impact_velocity: 1, static_friction: 0.3, kinetic_friction: 0.25, stiction_velocity: 1e-2}}\n";
    }
    const mbd::Model model = mbd::test::scene(scene.str());
    const mbd::ForceInstance& contact = element(model, "collision_contact");
    auto energy = [&](const mbd::State& s) {
        double E = 0.0;
        for (int b = 0; b < count; ++b) {
            const Eigen::Vector3d w = s.v.segment<3>(6 * b + 3);
            E += 0.5 * 0.1 * s.v.segment<3>(6 * b).squaredNorm() + 0.5 * w.dot(model.bodies[b].inertia * w) +
                 0.1 * kG * s.q[7 * b + 2];
        }
        ElementStates states(contact, s);
        return E + contact.force->potential_energy(states.view);
    };
    std::vector<double> E;
    run(model, "dopri5", t_end, tolerance, 0.005, [&](const mbd::State& s) { E.push_back(energy(s)); });
    ASSERT_EQ(E.size(), 61u);
    double rises = 0.0;
    for (size_t k = 1; k < E.size(); ++k) rises = std::max(rises, E[k] - E[k - 1]);
    // within a tenth of the integrator's relative tolerance (measured 6.1e-9 J of 24.1 J)
    EXPECT_LE(rises, 0.1 * tolerance * E.front()) << "largest rise between rows";
    RecordProperty("largest_rise", g17(rises));
    RecordProperty("energy_start", g17(E.front()));
    RecordProperty("energy_end", g17(E.back()));
    EXPECT_LT(E.back(), 0.8 * E.front()) << "the spheres collided and lost energy";
}

// ------------------------------------------------------------------ bad input
TEST(CollisionContact, BadShapesAndMaterialsAreRefusedNamingTheBody) {
    const std::string good = ball_scene(1e7, 0.8, 2.0, 0.5);
    struct Case {
        std::string from, to, says;
    };
    const std::vector<Case> cases = {
        {"radius: 0.1", "radius: 0", "'radius' must be positive"},
        {"radius: 0.1", "radius: -0.1", "'radius' must be positive"},
        {"restitution: 0.80000000000000004", "restitution: 1.2", "'restitution' must be in (0, 1]"},
        {"restitution: 0.80000000000000004", "restitution: -0.1", "'restitution' must be in (0, 1]"},
        {"impact_velocity: 2}", "impact_velocity: 2, static_friction: -0.1}", "'static_friction' must not be negative"},
        {"mass: 1", "mass: 0", "no mass"},
        {"shape: sphere\n        radius: 0.1", "shape: box\n        size: [0.1, 0, 0.1]", "'size' entries must be positive"},
        {"shape: sphere", "shape: cone", "'shape' must be sphere, capsule, cylinder, box, plane, convex_mesh or triangle_mesh"},
    };
    for (const Case& c : cases) {
        const std::string bad = mbd::test::replaced(good, c.from, c.to);
        try {
            mbd::test::scene(bad);
            ADD_FAILURE() << "accepted: " << c.to;
        } catch (const mbd::InputError& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find(c.says), std::string::npos) << what;
            EXPECT_NE(what.find("body 'ball'"), std::string::npos) << what;
        }
    }
    // through the command: exit code 2 and the message
    const auto dir = mbd::test::scratch("collision_bad");
    std::ofstream(dir / "bad.yaml") << mbd::test::replaced(good, "radius: 0.1", "radius: -0.1");
    const auto r = mbd::test::run_mbd("check " + (dir / "bad.yaml").string());
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    EXPECT_NE(r.err.find("body 'ball', collision shape 1 (sphere): 'radius' must be positive"), std::string::npos)
        << r.err;
}

// ------------------------------------------------------------------ Hertz materials
// Materials given by Young's modulus and Poisson's ratio: two equal steel spheres pressed
// together by delta, and one on a rigid plane, push with Hertz's F = 4/3 E* sqrt(R*) delta^1.5,
// 1/E* = sum (1 - nu^2) / E, 1/R* = sum 1/R (Johnson, Contact Mechanics, Eq. 4.22).
TEST(CollisionContact, YoungsModulusGivesHertzsForce) {
    const double E = 2.1e11, nu = 0.3, R = 0.05, delta = 1e-5;
    const std::string steel = "{young_modulus: 2.1e11, poisson_ratio: 0.3}";
    const std::string scene =
        "dimension: spatial\nground:\n  collision:\n    - {shape: plane, normal: [0, 0, 1]}\nbodies:\n"
        "  - {name: a, mass: 1, inertia: [0.001, 0.001, 0.001], position: [0, 0, 1], "
        "collision: [{shape: sphere, radius: 0.05, material: " + steel + "}]}\n"
        "  - {name: b, mass: 1, inertia: [0.001, 0.001, 0.001], position: [0, 0, 1.2], "
        "collision: [{shape: sphere, radius: 0.05, material: " + steel + "}]}\n";
    const mbd::Model model = mbd::test::scene(scene);
    const mbd::ForceInstance& f = element(model, "collision_contact");
    ASSERT_EQ(f.bodies.size(), 3u);  // ground, a, b
    mbd::State s;
    s.q.resize(14);
    s.v = Eigen::VectorXd::Zero(12);
    const Eigen::Vector3d axis = Eigen::Vector3d(0.3, -0.2, 1.0).normalized();
    s.q << 0.4, 0.1, R - delta, 1, 0, 0, 0, 0.4, 0.1, R - delta, 1, 0, 0, 0;
    s.q.segment<3>(7) += (2 * R - delta) * axis;  // b on a, overlapping by delta
    ElementStates states(f, s);
    Eigen::VectorXd Q = Eigen::VectorXd::Zero(18);
    f.force->evaluate(states.view, Q);
    const double sphere_sphere = 4.0 / 3.0 * (E / (2 * (1 - nu * nu))) * std::sqrt(R / 2) * std::pow(delta, 1.5);
    const double sphere_plane = 4.0 / 3.0 * (E / (1 - nu * nu)) * std::sqrt(R) * std::pow(delta, 1.5);
    // b: pushed along the axis by a only (it is clear of the plane)
    EXPECT_LT((Q.segment<3>(12) - sphere_sphere * axis).norm(), 1e-10 * sphere_sphere);
    // a: pushed back by b, up by the plane
    EXPECT_LT((Q.segment<3>(6) - (sphere_plane * Eigen::Vector3d::UnitZ() - sphere_sphere * axis)).norm(),
              1e-10 * sphere_plane);
    RecordProperty("sphere_sphere_force", g17(sphere_sphere));
    // Hertz needs a curved surface, and a Poisson ratio below 1/2
    for (const auto& [from, to, says] : std::vector<std::array<std::string, 3>>{
             {"poisson_ratio: 0.3}}]}\n  - {name: b", "poisson_ratio: 0.5}}]}\n  - {name: b", "'poisson_ratio' must be in [0, 0.5)"},
             {"shape: sphere, radius: 0.05, material: {young", "shape: box, size: [0.1, 0.1, 0.1], material: {young",
              "'young_modulus' gives Hertz's law of a curved surface"}}) {
        try {
            mbd::test::scene(mbd::test::replaced(scene, from, to));
            ADD_FAILURE() << "accepted: " << to;
        } catch (const mbd::InputError& e) {
            EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("body 'a'"), std::string::npos) << e.what();
        }
    }
}

// ------------------------------------------------------------------ which pairs touch
// Two overlapping spheres push each other apart, unless a joint connects their bodies or their
// groups and masks exclude each other; the ground's plane still pushes both.
TEST(CollisionContact, JoinedBodiesAndExcludedGroupsDoNotTouch) {
    const std::string base =
        "dimension: spatial\nground:\n  collision:\n    - {shape: plane, normal: [0, 0, 1]}\nbodies:\n"
        "  - {name: a, mass: 1, inertia: [0.001, 0.001, 0.001], position: [0, 0, 0.099], "
        "collision: [{shape: sphere, radius: 0.1, GROUP_A material: {stiffness: 1e6}}]}\n"
        "  - {name: b, mass: 1, inertia: [0.001, 0.001, 0.001], position: [0.15, 0, 0.099], "
        "collision: [{shape: sphere, radius: 0.1, GROUP_B material: {stiffness: 1e6}}]}\n";
    auto between = [&](const std::string& groups_a, const std::string& groups_b, const std::string& joints) {
        const std::string yaml =
            mbd::test::replaced(mbd::test::replaced(base, "GROUP_A ", groups_a), "GROUP_B ", groups_b) + joints;
        const mbd::Model model = mbd::test::scene(yaml);
        const mbd::ForceInstance& f = element(model, "collision_contact");
        mbd::State s;
        s.q.resize(14);
        s.v = Eigen::VectorXd::Zero(12);
        for (int b = 0; b < 2; ++b) s.q.segment<7>(7 * b) << model.bodies[b].position, 1, 0, 0, 0;
        ElementStates states(f, s);
        Eigen::VectorXd Q = Eigen::VectorXd::Zero(18);
        f.force->evaluate(states.view, Q);
        return std::make_pair(Q[12], Q[14]);  // on b: x (from a), z (from the plane)
    };
    const double plane = 1e6 * std::pow(0.001, 1.5);  // k d^n, 1 mm deep
    // 5 cm overlap of two equal materials in series: k^(-2/3) = 2 (1e6)^(-2/3), k = 1e6 / 2^1.5
    const double pair = 1e6 / std::pow(2.0, 1.5) * std::pow(0.05, 1.5);
    const auto touching = between("", "", "");
    EXPECT_NEAR(touching.first, pair, 1e-9 * pair);
    EXPECT_NEAR(touching.second, plane, 1e-9 * plane);
    const auto joined = between("", "", "joints:\n  - {name: link, type: spherical, bodies: [a, b], point: [0.075, 0, 0.099]}\n");
    EXPECT_EQ(joined.first, 0.0);
    EXPECT_NEAR(joined.second, plane, 1e-9 * plane);
    const auto excluded = between("group: 1, collides_with: [0, 1], ", "group: 2, collides_with: [0, 2], ", "");
    EXPECT_EQ(excluded.first, 0.0);
    EXPECT_NEAR(excluded.second, plane, 1e-9 * plane);
    const auto admitted = between("group: 1, collides_with: [0, 2], ", "group: 2, collides_with: [1], ", "");
    EXPECT_NEAR(admitted.first, pair, 1e-9 * pair);
    EXPECT_EQ(admitted.second, 0.0);  // b's mask leaves out the ground's group 0
}

}  // namespace
