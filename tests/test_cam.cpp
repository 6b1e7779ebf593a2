// The cam joint (plugins/joints/cam, book Sec. 3.4) against independent closed forms: the lift of a
// radial follower on a driven cam, for every follower type and profile, its velocity and
// acceleration from the differentiated closed forms; the contact force of a spring-loaded
// flat-faced follower from the follower's own Newton law, the Newton-Euler balance of every
// body with the joint reactions, and the lift-off warning at the closed-form time.
//
// Geometry of every case: the cam turns about the origin (revolute to the ground, driven at
// theta = w t); the follower slides along the world y axis (prismatic to the ground) above it.
// Eccentric circle: radius R, centre e (cos theta, sin theta). A point follower on the y axis
// at distance R + r from the centre (knife edge r = 0, roller radius r):
//     y = e sin(theta) + sqrt((R + r)^2 - e^2 cos^2(theta));
// a flat face normal to y touching the circle from above: y = R + e sin(theta). On a polar
// profile d(phi) the knife edge on the y axis touches the profile point at polar angle
// phi = pi/2 - theta (cam axes), so y = d(pi/2 - theta).
#include <mbd/kinematics.hpp>
#include <mbd/model_system.hpp>
#include <mbd/reactions.hpp>
#include <mbd/simulation.hpp>
#include <mbd/statics_analysis.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include "support/test_support.hpp"

namespace {

using mbd::test::g17;
using mbd::test::shared_registry;

constexpr double kR = 0.1, kE = 0.02;

// A cam (driven at w) and a follower on a vertical guide; `follower_keys` are the cam joint's
// follower keys, `y0` the follower's initial height (the assembly corrects a rough value).
std::string cam_scene(const std::string& profile, const std::string& follower_keys, double y0, double w,
                      const std::string& extra = "") {
    return "name: cam\ndimension: planar\ngravity: [0, -9.81]\nbodies:\n"
           "  - {name: cam, mass: 2, inertia: 0.01, position: [0, 0]}\n"
           "  - {name: follower, mass: 0.5, inertia: 0.001, position: [0, " + g17(y0) + "]}\n"
           "joints:\n"
           "  - {name: O, type: revolute, bodies: [ground, cam], point: [0, 0]}\n"
           "  - {name: guide, type: prismatic, bodies: [ground, follower], point: [0, " + g17(y0) + "], axis: [0, 1]}\n"
           "  - {name: contact, type: cam, bodies: [cam, follower], point: [0, 0], profile: " + profile + ", " +
           follower_keys + "}\n"
           "drivers:\n  - {name: motor, joint: O, motion: {type: linear, initial: 0, rate: " + g17(w) + "}}\n" + extra;
}

const std::string kEccentric = "{type: eccentric, radius: " + g17(kR) + ", eccentricity: " + g17(kE) + "}";

struct Lift {
    double y, ydot, yddot;
};

// Point follower on the eccentric circle (radius a = R + r), theta = w t.
Lift eccentric_point_lift(double a, double w, double t) {
    const double th = w * t, s = std::sin(th), c = std::cos(th);
    const double S = std::sqrt(a * a - kE * kE * c * c);
    const double y1 = kE * c + kE * kE * c * s / S;
    const double y2 = -kE * s + kE * kE * std::cos(2 * th) / S - std::pow(kE, 4) * c * c * s * s / (S * S * S);
    return {kE * s + S, w * y1, w * w * y2};
}

// The follower's height, rate and acceleration along a kinematic run, at every sample.
void check_lift(const mbd::Model& model, double t_end, double step, const std::function<Lift(double)>& exact,
                double tolerance, int* samples = nullptr) {
    double worst = 0.0;
    int n = 0;
    mbd::run_kinematics(model, t_end, step, [&](const mbd::State& s, const Eigen::VectorXd& a) {
        const Lift e = exact(s.t);
        worst = std::max({worst, std::abs(s.q[4] - e.y), std::abs(s.v[4] - e.ydot), std::abs(a[4] - e.yddot)});
        ++n;
        return true;
    });
    EXPECT_GT(n, 10);
    EXPECT_LE(worst, tolerance);
    std::cout << "largest |y - y_exact|, |ydot - ...|, |yddot - ...| over " << n << " samples: " << worst << "\n";
    if (samples) *samples = n;
}

TEST(Cam, KnifeEdgeOnEccentricCircleFollowsTheClosedFormLift) {
    const double w = 7.0;
    const mbd::Model m = mbd::test::scene(cam_scene(kEccentric, "follower: knife_edge, follower_point: [0, 0]", 0.12, w));
    check_lift(m, 1.0, 0.01, [&](double t) { return eccentric_point_lift(kR, w, t); }, 1e-10);
}

TEST(Cam, RollerOnEccentricCircleFollowsTheClosedFormLift) {
    const double w = 7.0, r = 0.03;
    // the roller centre 0.01 below the follower's mass centre
    const mbd::Model m = mbd::test::scene(
        cam_scene(kEccentric, "follower: roller, radius: " + g17(r) + ", follower_point: [0, -0.01]", 0.14, w));
    check_lift(m, 1.0, 0.01, [&](double t) {
        Lift l = eccentric_point_lift(kR + r, w, t);
        l.y += 0.01;
        return l;
    }, 1e-10);
}

TEST(Cam, FlatFaceOnEccentricCircleFollowsTheClosedFormLift) {
    const double w = 7.0;
    const mbd::Model m = mbd::test::scene(
        cam_scene(kEccentric, "follower: flat_face, follower_point: [0.005, -0.02], face_normal: [0, -1]", 0.13, w));
    check_lift(m, 1.0, 0.01, [&](double t) {
        const double th = w * t;
        return Lift{kR + 0.02 + kE * std::sin(th), kE * w * std::cos(th), -kE * w * w * std::sin(th)};
    }, 1e-10);
}

TEST(Cam, KnifeEdgeOnHarmonicProfileFollowsTheRadius) {
    const double w = 5.0, a0 = 0.1, a1 = 0.01, b2 = 0.004, a3 = -0.002;
    const std::string profile = "{type: harmonic, base: " + g17(a0) + ", cos: [" + g17(a1) + ", 0, " + g17(a3) +
                                "], sin: [0, " + g17(b2) + "]}";
    const mbd::Model m = mbd::test::scene(cam_scene(profile, "follower: knife_edge, follower_point: [0, 0]", 0.1, w));
    check_lift(m, 1.3, 0.01, [&](double t) {
        // y = d(phi), phi = pi/2 - w t: ydot = -w d'(phi), yddot = w^2 d''(phi)
        const double p = M_PI / 2 - w * t;
        const double d = a0 + a1 * std::cos(p) + b2 * std::sin(2 * p) + a3 * std::cos(3 * p);
        const double d1 = -a1 * std::sin(p) + 2 * b2 * std::cos(2 * p) - 3 * a3 * std::sin(3 * p);
        const double d2 = -a1 * std::cos(p) - 4 * b2 * std::sin(2 * p) - 9 * a3 * std::cos(3 * p);
        return Lift{d, -w * d1, w * w * d2};
    }, 1e-10);
}

// The periodic cubic spline through d_k = a + b cos(phi_k), phi_k = k h, h = 2 pi / n: the
// nodal second derivatives of the cyclic system M_k-1 + 4 M_k + M_k+1 = 6 (d_k+1 - 2 d_k +
// d_k-1) / h^2 are, for this single Fourier mode, M_k = b cos(phi_k) 6 (2 cos h - 2) / (h^2 (4 +
// 2 cos h)), and the slope at a node is d'_k = (d_k+1 - d_k) / h - h (2 M_k + M_k+1) / 6. The
// knife edge is at the node phi_k whenever pi/2 - w t = phi_k.
TEST(Cam, KnifeEdgeOnPeriodicSplineProfileMeetsTheNodes) {
    const int n = 8;
    const double a = 0.1, b = 0.015, h = 2 * M_PI / n;
    std::vector<double> d(n), M(n);
    std::string radii;
    for (int k = 0; k < n; ++k) {
        d[k] = a + b * std::cos(k * h);
        M[k] = b * std::cos(k * h) * 6 * (2 * std::cos(h) - 2) / (h * h * (4 + 2 * std::cos(h)));
        radii += (k ? ", " : "") + g17(d[k]);
    }
    const double step = 0.1, w = h / step;  // one node per output step
    const mbd::Model m = mbd::test::scene(
        cam_scene("{type: spline, radii: [" + radii + "]}", "follower: knife_edge, follower_point: [0, 0]", 0.1, w));
    double worst = 0.0;
    int nodes = 0;
    mbd::run_kinematics(m, 1.6, step, [&](const mbd::State& s, const Eigen::VectorXd& acc) {
        const int j = static_cast<int>(std::lround(s.t / step));
        const int k = ((2 - j) % n + n) % n;  // phi = pi/2 - j h = phi_k
        const double slope = (d[(k + 1) % n] - d[k]) / h - h * (2 * M[k] + M[(k + 1) % n]) / 6;
        worst = std::max({worst, std::abs(s.q[4] - d[k]), std::abs(s.v[4] + w * slope),
                          std::abs(acc[4] - w * w * M[k])});
        ++nodes;
        return true;
    });
    EXPECT_EQ(nodes, 17);
    EXPECT_LE(worst, 1e-10);
    std::cout << "spline nodes: largest lift / rate / acceleration error " << worst << "\n";
}

// --- dynamics: a spring-loaded flat-faced follower on the eccentric cam driven at w.
// Follower (mass m, gravity g) pushed down by a spring of stiffness k from the ground point
// (0, H), rest length L0: its Newton law along y, m yddot = N - m g - k (L0 - H + y), with
// y = R + e sin(w t) gives the contact force
//     N(t) = m g + F0 + (k - m w^2) e sin(w t),   F0 = k (L0 - H + R),
// which reaches zero (the follower would lift off) at sin(w t*) = (m g + F0) / ((m w^2 - k) e).
struct SpringLoaded {
    double m = 0.5, g = 9.81, k = 200, H = 0.5, L0 = 0.405, w = 40;
    double F0() const { return k * (L0 - H + kR); }
    double N(double t) const { return m * g + F0() + (k - m * w * w) * kE * std::sin(w * t); }
    double lift_off() const { return std::asin((m * g + F0()) / ((m * w * w - k) * kE)) / w; }
    std::string scene() const {
        return cam_scene(kEccentric, "follower: flat_face, follower_point: [0, 0], face_normal: [0, -1]", kR, w,
                         "forces:\n  - {name: spring, type: spring_damper, bodies: [ground, follower], points: [[0, " +
                             g17(H) + "], [0, 0]], stiffness: " + g17(k) + ", rest_length: " + g17(L0) + "}\n");
    }
};

// M vdot - Q_applied - (sum of the reactions of every joint and driver), each reaction moved
// back from its joint point to the mass centre with the scene's marker geometry.
double newton_euler_residual(const mbd::Model& model, const mbd::State& state, const Eigen::VectorXd& lambda,
                             const Eigen::VectorXd& vdot, mbd::System& system) {
    Eigen::VectorXd Q;
    system.generalized_forces(state, Q);
    std::vector<mbd::JointReaction> all = mbd::joint_reactions(system, state, lambda);
    for (auto& d : mbd::driver_reactions(system, state, lambda)) all.push_back(d);
    Eigen::VectorXd balance = system.mass_matrix() * vdot - Q;
    for (const mbd::JointReaction& r : all) {
        const mbd::JointInstance& joint = model.joints[r.driver ? model.drivers[r.element].joint : r.element];
        for (size_t k = 0; k < r.on.size(); ++k) {
            const int b = joint.bodies[k];
            if (b < 0) continue;
            const Eigen::Vector2d u = mbd::planar_rotation(state.q[3 * b + 2]) * joint.markers[k].u_bar2();
            balance.segment<2>(3 * b) -= r.on[k].force.head<2>();
            balance[3 * b + 2] -= r.on[k].torque.z() + (u.x() * r.on[k].force.y() - u.y() * r.on[k].force.x());
        }
    }
    return balance.lpNorm<Eigen::Infinity>();
}

TEST(Cam, DrivenCamReactionsBalanceEveryBodyAndGiveTheClosedFormContactForce) {
    const SpringLoaded c;
    const mbd::Model model = mbd::test::scene(c.scene());
    mbd::ModelSystem system(model);
    mbd::Param node;
    auto formulation = mbd::test::make_formulation("augmented", node);
    formulation->bind(system, mbd::FormulationOptions{});
    const mbd::SimulationSettings settings = mbd::test::adaptive_run("augmented", "dopri5", 1e-10, 0.16, 0.002);
    double balance = 0.0, force = 0.0, scale = 0.0, violation = 0.0;
    int samples = 0;
    mbd::simulate(model, shared_registry(), settings, [&](const mbd::SimulationSample& s) {
        Eigen::VectorXd lambda, vdot;
        formulation->multipliers(s.state, lambda);
        formulation->accelerations(s.state, vdot);
        balance = std::max(balance, newton_euler_residual(model, s.state, lambda, vdot, system));
        // the contact's reaction on the follower (body 1): the normal force, +y on the follower
        const auto reactions = mbd::joint_reactions(system, s.state, lambda);
        const mbd::Vec3 F = reactions[2].on[1].force;
        force = std::max({force, std::abs(F.y() - c.N(s.state.t)), std::abs(F.x())});
        scale = std::max(scale, std::abs(c.N(s.state.t)));
        mbd::ConstraintValues cv;
        system.constraints(s.state, cv);
        violation = std::max(violation, cv.C.lpNorm<Eigen::Infinity>());
        ++samples;
        return true;
    });
    EXPECT_EQ(samples, 81);
    EXPECT_LE(balance, 1e-9);
    EXPECT_LE(force, 1e-9 * scale) << "scale " << scale;
    EXPECT_LE(violation, 1e-10);
    std::cout << "Newton-Euler residual " << balance << ", contact force error " << force << " (N up to " << scale
              << "), max |C| " << violation << "\n";
}

TEST(Cam, SpringLoadedFollowerWarnsWhereItsContactForceReachesZero) {
    const SpringLoaded c;
    const mbd::Model model = mbd::test::scene(c.scene());
    std::vector<std::string> lines;
    // to 0.1 s: one lift-off (t* = 0.0129 s) and one return to compression
    mbd::SimulationSettings settings = mbd::test::adaptive_run("augmented", "dopri5", 1e-10, 0.1, 1e-4);
    settings.messages = mbd::MessageLog([&](const std::string& line) { lines.push_back(line); });
    const mbd::SimulationResult r = mbd::simulate(model, shared_registry(), settings);
    ASSERT_EQ(r.lift_offs.size(), 1u);
    EXPECT_EQ(r.lift_offs[0].joint, "contact");
    EXPECT_NEAR(r.lift_offs[0].time, c.lift_off(), 1e-7);
    std::cout << "lift-off at t = " << r.lift_offs[0].time << " s, closed form " << c.lift_off() << " s\n";
    int warnings = 0;
    for (const std::string& line : lines)
        if (line.find("warning: joint 'contact' (contact): the contact force reaches zero at t = ") != std::string::npos)
            ++warnings;
    EXPECT_EQ(warnings, 1);
}

// Statics: the free cam (no driver) settles where the spring-loaded flat face is lowest,
// theta = -pi/2 (y = R - e), and the contact force is then the spring's push plus the
// follower's weight, N = m g + k (L0 - H + R - e), along +y.
TEST(Cam, StaticsFindsTheLowestFollowerAndItsContactForce) {
    const SpringLoaded c;
    std::string yaml = mbd::test::replaced(c.scene(), "drivers:\n  - {name: motor, joint: O, motion: {type: linear, initial: 0, rate: " +
                                                          g17(c.w) + "}}\n",
                                           "");
    yaml = mbd::test::replaced(yaml, "position: [0, 0]}", "position: [0, 0], angle: -1.2}");
    const mbd::Model model = mbd::test::scene(yaml);
    const mbd::StaticsReport rep = mbd::run_statics(model, shared_registry(), mbd::StaticsOptions{});
    ASSERT_TRUE(rep.result.converged) << rep.result.message;
    EXPECT_EQ(rep.result.stability, "stable");
    // the profile frame is world-aligned at t = 0 (markers coincide), so the cam turns by -pi/2
    EXPECT_NEAR(rep.result.state.q[2], -1.2 - M_PI / 2, 1e-7);
    EXPECT_NEAR(rep.result.state.q[4], kR - kE, 1e-10);
    const double N = c.m * c.g + c.k * (c.L0 - c.H + kR - kE);
    EXPECT_NEAR(rep.reactions[2].force.y(), N, 1e-7 * N);
    EXPECT_NEAR(rep.reactions[2].force.x(), 0.0, 1e-7 * N);
}

// Every formulation treats the contact as one holonomic row (tests/test_cross_formulation.cpp
// runs scenes/examples/planar-cam.yaml with each); only the recursive embedding path, which needs
// a tree of joints with relative coordinates, refuses it by name (docs/formulations.md).
TEST(Cam, TheRecursiveEmbeddingPathRefusesTheCamByName) {
    const std::string yaml = mbd::test::read_text(mbd::test::scene_path("examples/planar-cam.yaml")) +
                             "formulation: {type: embedding, path: recursive}\n";
    const mbd::Model model = mbd::test::scene(yaml);
    mbd::SimulationSettings settings;
    settings.t_end = 0.1;
    settings.progress = false;
    settings.messages = mbd::MessageLog::silent();
    try {
        mbd::simulate(model, shared_registry(), settings);
        ADD_FAILURE() << "the recursive path ran a scene with a cam joint";
    } catch (const std::exception& e) {
        EXPECT_NE(std::string(e.what()).find("recursive path needs a tree"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("cut joint 'contact'"), std::string::npos) << e.what();
    }
}

TEST(Cam, BadKeysAreNamed) {
    const std::string good = cam_scene("{type: eccentric, radius: 0.1, eccentricity: 0.02}",
                                       "follower: roller, radius: 0.03, follower_point: [0, 0]", 0.13, 1.0);
    EXPECT_NO_THROW(mbd::test::scene(good));
    const auto error_of = [&](const std::string& from, const std::string& to) {
        try {
            mbd::test::scene(mbd::test::replaced(good, from, to));
        } catch (const std::exception& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_NE(error_of("follower: roller", "follower: needle").find("unknown follower 'needle'"), std::string::npos);
    EXPECT_NE(error_of("eccentricity: 0.02", "eccentricity: 0.2").find("'eccentricity' must be less than"),
              std::string::npos);
    EXPECT_NE(error_of("radius: 0.03", "radius: -1").find("'radius' must be positive"), std::string::npos);
    EXPECT_NE(error_of("type: eccentric", "type: oval").find("unknown profile type 'oval'"), std::string::npos);
}

}  // namespace
