// Event-located impacts between collision shapes (issue 39, item 3; the material's `impact:`,
// plugins/forces/collision_contact/collision_impacts.hpp), against closed forms:
//  - a sphere dropped from h onto a plane: each impact at the time of free fall and flight,
//    each rebound to e^2 times the height before (the apex of every flight from its samples:
//    z - r + vz^2 / (2 g), constant in free flight), a finite number of bounces (the last
//    rebound faster than rest_velocity), then at rest on the plane at the depth of its weight
//    under the compliant law, (m g / k)^(1/n);
//  - two free spheres hitting head on (equal and unequal masses): momentum conserved to
//    round-off, the velocities after from Newton's law and the momentum balance;
//  - a pendulum striking a wall obliquely (the wall a body welded to the ground): the impulse
//    passes through the revolute joint, so the kinetic energy after is e^2 times before
//    (omega+ = -e omega-), the pivot stays in place and the wall does not move;
//  - every test with each formulation (augmented, embedding, amalgamated, hamiltonian), the drop
//    also with dop853 and cvode; a fixed-step integrator and impacts on a shape whose gap is not
//    exact are refused by name.
#include "support/test_support.hpp"

#include <mbd/simulation.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace {

using mbd::test::g17;

constexpr double kG = 9.81;

struct Sample {
    double t;
    mbd::State state;
};

struct Outcome {
    mbd::SimulationResult result;
    std::vector<Sample> samples;
};

Outcome simulate(const mbd::Model& model, const std::string& formulation, double t_end, double output_step,
             const std::string& integrator = "dopri5") {
    mbd::SimulationSettings s;
    s.formulation = formulation;
    s.integrator = integrator;
    s.integration.tolerance = 1e-12;
    s.t_end = t_end;
    s.output_step = output_step;
    s.progress = false;
    s.messages = mbd::MessageLog::silent();
    Outcome r;
    r.result = mbd::simulate(model, mbd::test::shared_registry(), s, [&](const mbd::SimulationSample& x) {
        r.samples.push_back({x.state.t, x.state});
        return true;
    });
    return r;
}

const char* const kFormulations[] = {"augmented", "embedding", "amalgamated", "hamiltonian"};

// ------------------------------------------------------------------ a sphere on a plane
struct Drop {
    double m = 1.0, r = 0.1, h = 1.0, e = 0.8, rest_velocity = 0.05;
    double k = 1e7, n = 1.5, c = 4e8;  // the compliant law that holds it at rest (damped)
    double v1() const { return std::sqrt(2 * kG * h); }
    std::string yaml() const {
        return "dimension: spatial\ngravity: [0, 0, -9.81]\n"
               "ground:\n  collision:\n    - {shape: plane, normal: [0, 0, 1]}\n"
               "bodies:\n  - name: ball\n    mass: " + g17(m) + "\n    inertia: [0.004, 0.004, 0.004]\n"
               "    position: [0, 0, " + g17(h + r) + "]\n"
               "    collision:\n      - shape: sphere\n        radius: " + g17(r) + "\n"
               "        material: {stiffness: " + g17(k) + ", exponent: " + g17(n) + ", damping: " + g17(c) +
               ", impact: {restitution: " + g17(e) + ", rest_velocity: " + g17(rest_velocity) + "}}\n";
    }
};

TEST(CollisionImpact, ASphereDroppedOnAPlaneReboundsToESquaredTimesEachHeightThenRests) {
    const Drop d;
    const mbd::Model model = mbd::test::scene(d.yaml());
    // impact k (from 0) comes at the speed e^k v1 and rebounds at e^(k+1) v1 while that is at
    // least the rest velocity: N impacts, then a plastic one (a rest)
    int N = 0;
    while (std::pow(d.e, N + 1) * d.v1() >= d.rest_velocity) ++N;
    std::vector<double> t_hit{std::sqrt(2 * d.h / kG)};
    for (int k = 1; k <= N; ++k) t_hit.push_back(t_hit.back() + 2 * std::pow(d.e, k) * d.v1() / kG);
    const double t_end = t_hit.back() + 0.3;
    // every formulation with dopri5, and the other two integrators that locate events
    const std::vector<std::pair<std::string, std::string>> methods = {
        {"augmented", "dopri5"}, {"embedding", "dopri5"}, {"amalgamated", "dopri5"}, {"hamiltonian", "dopri5"},
        {"augmented", "dop853"}, {"embedding", "cvode"}};
    for (const auto& [formulation, integrator] : methods) {
        SCOPED_TRACE(formulation + " " + integrator);
        const Outcome run = simulate(model, formulation, t_end, 1e-3, integrator);
        const auto& events = run.result.events;
        ASSERT_EQ(events.size(), static_cast<size_t>(N + 1));
        double worst_time = 0, worst_rate = 0, worst_apex = 0;
        for (int k = 0; k <= N; ++k) {
            const mbd::EventRecord& hit = events[k];
            EXPECT_EQ(hit.kind, k < N ? "impact" : "rest") << k;
            EXPECT_NE(hit.event.find("body 'ball', collision shape 1 (sphere)"), std::string::npos) << hit.event;
            worst_time = std::max(worst_time, std::abs(hit.time - t_hit[k]));
            worst_rate = std::max(worst_rate, std::abs(hit.rate_before + std::pow(d.e, k) * d.v1()));
            EXPECT_NEAR(hit.rate_after, k < N ? -d.e * hit.rate_before : 0.0, 1e-12) << k;
        }
        // every flight's apex from its samples, against e^(2(k+1)) h
        int flights_seen = 0;
        for (int k = 0; k < N; ++k) {
            const double expected = std::pow(d.e, 2 * (k + 1)) * d.h;
            bool seen = false;
            for (const Sample& s : run.samples) {
                if (!(s.t > events[k].time + 1e-9 && s.t < events[k + 1].time - 1e-9)) continue;
                const double apex = s.state.q[2] - d.r + s.state.v[2] * s.state.v[2] / (2 * kG);
                worst_apex = std::max(worst_apex, std::abs(apex - expected));
                seen = true;
            }
            flights_seen += seen;
        }
        EXPECT_EQ(flights_seen, N);
        std::printf("%s %s: %d impacts and a rest; worst impact time error %.3g s, approach speed %.3g m/s, apex "
                    "%.3g m\n", formulation.c_str(), integrator.c_str(), N, worst_time, worst_rate, worst_apex);
        // the Runge-Kutta methods integrate free flight (a quadratic in t) exactly, so only the
        // location's round-off remains; cvode's BDF solution is as accurate as its tolerance
        const double bound = integrator == "cvode" ? 1e-8 : 1e-12;
        EXPECT_LT(worst_time, bound);
        EXPECT_LT(worst_rate, bound);
        EXPECT_LT(worst_apex, 1e-9);
        // at rest on the plane, pressed in by its weight: k delta^n = m g
        const mbd::State& last = run.samples.back().state;
        const double depth = std::pow(d.m * kG / d.k, 1.0 / d.n);
        EXPECT_NEAR(d.r - last.q[2], depth, 1e-9 * depth);
        EXPECT_LT(last.v.head<3>().norm(), 1e-9);
        // never deeper than the resting depth's overshoot: no impact passed through the plane
        double deepest = 0.0;
        for (const Sample& s : run.samples) deepest = std::max(deepest, d.r - s.state.q[2]);
        EXPECT_LT(deepest, 2.0 * depth);
    }
}

// ------------------------------------------------------------------ two free spheres
// Sphere a (mass m_a) at speed u along x hits sphere b (m_b) at rest, head on, without
// gravity: Newton's law and the momentum balance give
//     v_a = (m_a - e m_b) u / (m_a + m_b),   v_b = (1 + e) m_a u / (m_a + m_b).
TEST(CollisionImpact, TwoFreeSpheresHittingHeadOnConserveMomentumAndSeparateAtETimesTheApproach) {
    const double u = 2.0, e = 0.6, r = 0.1, gap = 0.3;
    for (const double m_b : {1.0, 3.0}) {
        const double m_a = 1.0;
        SCOPED_TRACE("m_b " + g17(m_b));
        const auto body = [&](const std::string& name, double m, double x, double v) {
            return "  - name: " + name + "\n    mass: " + g17(m) + "\n    inertia: [0.004, 0.004, 0.004]\n"
                   "    position: [" + g17(x) + ", 0, 0]\n    velocity: [" + g17(v) + ", 0, 0]\n"
                   "    collision:\n      - {shape: sphere, radius: " + g17(r) +
                   ", material: {stiffness: 1.0e7, impact: {restitution: " + g17(e) + "}}}\n";
        };
        const mbd::Model model = mbd::test::scene("dimension: spatial\ngravity: [0, 0, 0]\nbodies:\n" +
                                                  body("a", m_a, 0.0, u) + body("b", m_b, 2 * r + gap, 0.0));
        const double t_hit = gap / u;
        for (const char* formulation : kFormulations) {
            SCOPED_TRACE(formulation);
            const Outcome run = simulate(model, formulation, 2 * t_hit, t_hit / 10);
            ASSERT_EQ(run.result.events.size(), 1u);
            const mbd::EventRecord& hit = run.result.events[0];
            EXPECT_EQ(hit.kind, "impact");
            EXPECT_NEAR(hit.time, t_hit, 1e-12);
            EXPECT_NEAR(hit.rate_before, -u, 1e-12);
            const mbd::State& last = run.samples.back().state;
            const double va = last.v[0], vb = last.v[6];
            EXPECT_NEAR(va, (m_a - e * m_b) * u / (m_a + m_b), 1e-12);
            EXPECT_NEAR(vb, (1 + e) * m_a * u / (m_a + m_b), 1e-12);
            EXPECT_NEAR(m_a * va + m_b * vb, m_a * u, 1e-14 * m_a * u);  // momentum, to round-off
            EXPECT_NEAR(vb - va, e * u, 1e-12);
            // nothing sideways, no spin: a head-on impulse along the line of centres
            EXPECT_LT(last.v.segment<2>(1).norm() + last.v.segment<2>(7).norm(), 1e-14);
            EXPECT_LT(last.v.segment<3>(3).norm() + last.v.segment<3>(9).norm(), 1e-14);
            // the spheres separate: the gap at the end is (v_b - v_a) (t_end - t_hit)
            EXPECT_NEAR(last.q[7] - last.q[0] - 2 * r, e * u * t_hit, 1e-10);
        }
    }
}

// ------------------------------------------------------------------ a pendulum on a wall
// A bob (mass m, J about its centre) on a massless arm of length L pivoted at the origin about
// world y, released at phi0 from the vertical, swings down onto a wall: a large sphere welded
// to the ground, touching the bob when it hangs straight down, with the contact normal tilted
// by beta from the horizontal (so the impulse also pulls along the arm, which the pivot takes).
// With the pendulum's one coordinate phi, gdot = c phidot, so Newton's law on the constrained
// system gives phidot+ = -e phidot-: the kinetic energy after is e^2 times before, which was
// m g L (1 - cos phi0) (I_O = J + m L^2).
TEST(CollisionImpact, APendulumStrikingAWallReboundsWithMinusETimesItsAngularVelocityThroughTheJoint) {
    const double m = 1.5, J = 0.02, L = 0.8, phi0 = 1.0, e = 0.7, rb = 0.05, rw = 0.5, beta = 0.4;
    const double I_O = J + m * L * L;
    const double reach = rb + rw;
    const std::string scene =
        "dimension: spatial\ngravity: [0, 0, -9.81]\n"
        "bodies:\n"
        "  - name: bob\n    mass: " + g17(m) + "\n    inertia: [" + g17(J) + ", " + g17(J) + ", " + g17(J) + "]\n"
        "    position: [" + g17(L * std::sin(phi0)) + ", 0, " + g17(-L * std::cos(phi0)) + "]\n"
        "    collision:\n      - {shape: sphere, radius: " + g17(rb) +
        ", material: {stiffness: 1.0e8, impact: {restitution: " + g17(e) + "}}}\n"
        "  - name: wall\n    mass: 10\n    inertia: [1, 1, 1]\n"
        "    position: [" + g17(-reach * std::cos(beta)) + ", 0, " + g17(-L + reach * std::sin(beta)) + "]\n"
        "    collision:\n      - {shape: sphere, radius: " + g17(rw) + ", material: {stiffness: 1.0e8}}\n"
        "joints:\n"
        "  - {name: pivot, type: revolute, bodies: [ground, bob], point: [0, 0, 0], axis: [0, 1, 0]}\n"
        "  - {name: weld, type: fixed, bodies: [ground, wall], point: [0, 0, 0]}\n";
    const mbd::Model model = mbd::test::scene(scene);
    const Eigen::Vector3d wall0(-reach * std::cos(beta), 0, -L + reach * std::sin(beta));
    const double T_before = m * kG * L * (1 - std::cos(phi0));
    for (const char* formulation : kFormulations) {
        SCOPED_TRACE(formulation);
        const Outcome run = simulate(model, formulation, 1.0, 1e-3);
        ASSERT_GE(run.result.events.size(), 1u);
        const mbd::EventRecord& hit = run.result.events[0];
        EXPECT_EQ(hit.kind, "impact");
        EXPECT_NEAR(hit.rate_after, -e * hit.rate_before, 1e-12);
        // the energy of every sample between this impact and the next (or the end): free swing
        const double t_next = run.result.events.size() > 1 ? run.result.events[1].time : 1.0;
        double worst_energy = 0, worst_arm = 0, worst_wall = 0;
        int seen = 0;
        for (const Sample& s : run.samples) {
            const Eigen::Vector3d R = s.state.q.head<3>(), Rdot = s.state.v.head<3>();
            worst_arm = std::max(worst_arm, std::abs(R.norm() - L));
            worst_wall = std::max(worst_wall, (s.state.q.segment<3>(7) - wall0).norm());
            if (!(s.t > hit.time + 1e-9 && s.t < t_next - 1e-9)) continue;
            // omega about y from the bob's velocity (R = L (sin phi, 0, -cos phi))
            const double phidot = (R.z() * Rdot.x() - R.x() * Rdot.z()) / (L * L);
            const double kinetic_at_bottom = 0.5 * I_O * phidot * phidot + m * kG * (R.z() + L);
            worst_energy = std::max(worst_energy, std::abs(kinetic_at_bottom - e * e * T_before));
            ++seen;
        }
        std::printf("%s: impact at %.12f, energy after vs e^2 before %.3g J, arm %.3g m, wall %.3g m\n", formulation,
                    hit.time, worst_energy, worst_arm, worst_wall);
        EXPECT_GT(seen, 10);
        EXPECT_LT(worst_energy, 1e-8 * T_before);
        EXPECT_LT(worst_arm, 1e-9);
        EXPECT_LT(worst_wall, 1e-9);
    }
}

// ------------------------------------------------------------------ refusals
TEST(CollisionImpact, FixedStepIntegratorsAndShapesWithoutAnExactGapAreRefusedByName) {
    const Drop d;
    const mbd::Model model = mbd::test::scene(d.yaml());
    try {
        simulate(model, "augmented", 0.1, 0.01, "rk4");
        ADD_FAILURE() << "rk4 accepted";
    } catch (const mbd::InputError& error) {
        const std::string what = error.what();
        EXPECT_NE(what.find("does not locate events"), std::string::npos) << what;
        EXPECT_NE(what.find("collision_contact"), std::string::npos) << what;
    }
    struct Case {
        std::string from, to, says;
    };
    const std::vector<Case> cases = {
        {"shape: sphere\n        radius: 0.10000000000000001", "shape: box\n        size: [0.2, 0.2, 0.2]",
         "is located between spheres and planes only"},
        {"restitution: 0.80000000000000004", "restitution: 1.5", "'impact.restitution' must lie in [0, 1]"},
        {"rest_velocity: 0.050000000000000003", "rest_velocity: 0", "'impact.rest_velocity' must be positive"},
        {"rest_velocity: 0.050000000000000003", "rest_speed: 0.1", "unknown key 'impact.rest_speed'"},
        {"impact: {restitution: 0.80000000000000004, rest_velocity: 0.050000000000000003}", "impact: 0.8",
         "'impact' must be a map"},
    };
    for (const Case& c : cases) {
        const std::string bad = mbd::test::replaced(d.yaml(), c.from, c.to);
        ASSERT_NE(bad, d.yaml()) << c.from;
        try {
            mbd::test::scene(bad);
            ADD_FAILURE() << "accepted: " << c.to;
        } catch (const mbd::InputError& error) {
            const std::string what = error.what();
            EXPECT_NE(what.find(c.says), std::string::npos) << what;
            EXPECT_NE(what.find("body 'ball'"), std::string::npos) << what;
        }
    }
}

}  // namespace
