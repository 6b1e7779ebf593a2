// Joint stops in dynamics (issue 19, item 4): the joint_stop force element, event location
// in dopri5, dop853 and cvode, and Newton's impact law on the constrained system.
//  - A planar pendulum (pivot at the origin, mass centre at l, J about it) released at
//    phi0 onto a stop at the bottom (lower: 0) with restitution e: it hits at the quarter
//    period K(sin(phi0/2)) / w0 (w0^2 = m g l / I_O, K by the arithmetic-geometric mean),
//    rebounds with phidot+ = -e phidot-, and rises to the height e^2 times the drop, which it
//    reaches a quarter period K(sin(phi1/2)) / w0 later.
//  - A free wheel turning into a compliant Hunt-Crossley stop: the rebound speed against the
//    contact's 1-DOF ODE J delta'' = -delta^n (k + c delta') integrated here with RK4.
#include "support/test_support.hpp"

#include <mbd/contact_events.hpp>
#include <mbd/integrator.hpp>
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

// K(k), the complete elliptic integral of the first kind: pi / (2 AGM(1, sqrt(1 - k^2))).
double elliptic_k(double k) {
    double a = 1.0, b = std::sqrt(1.0 - k * k);
    for (int i = 0; i < 40 && std::abs(a - b) > 1e-16 * a; ++i) {
        const double m = 0.5 * (a + b);
        b = std::sqrt(a * b);
        a = m;
    }
    return kPi / (2.0 * a);
}

struct Pendulum {
    double m = 1.5, l = 0.8, J = 0.02, phi0 = 1.2, e = 0.6, lower = 0.0;
    double inertia() const { return J + m * l * l; }                   // about the pivot
    double w0() const { return std::sqrt(m * kG * l / inertia()); }
    double quarter(double amplitude) const { return elliptic_k(std::sin(amplitude / 2)) / w0(); }
    double drop() const { return l * (1.0 - std::cos(phi0)); }
    // the amplitude after the impact: 1 - cos(phi1) = e^2 (1 - cos(phi0))
    double phi1() const { return std::acos(1.0 - e * e * (1.0 - std::cos(phi0))); }
    std::string yaml(const std::string& stop_keys) const {
        // the body angle is the pendulum's angle from the vertical (body x axis along the rod's normal)
        return "name: pendulum-stop\ndimension: planar\ngravity: [0, -9.81]\n"
               "bodies:\n  - {name: bob, mass: " + g17(m) + ", inertia: " + g17(J) + ", position: [" +
               g17(l * std::sin(phi0)) + ", " + g17(-l * std::cos(phi0)) + "], angle: " + g17(phi0) + "}\n"
               "joints:\n  - {name: pivot, type: revolute, bodies: [ground, bob], point: [0, 0]}\n"
               "forces:\n  - {name: stop, type: joint_stop, bodies: [ground, bob], lower: " + g17(lower) + ", " + stop_keys + "}\n";
    }
};

mbd::SimulationSettings settings(const std::string& integrator, double t_end, double output_step, double tol) {
    mbd::SimulationSettings s;
    s.formulation = "augmented";
    s.integrator = integrator;
    s.integration.tolerance = tol;
    s.t_end = t_end;
    s.output_step = output_step;
    s.progress = false;
    s.messages = mbd::MessageLog::silent();
    return s;
}

struct Outcome {
    mbd::SimulationResult result;
    std::vector<mbd::State> states;
};

Outcome simulate(const mbd::Model& model, const mbd::SimulationSettings& s) {
    Outcome r;
    r.result = mbd::simulate(model, mbd::test::shared_registry(), s, [&](const mbd::SimulationSample& sample) {
        r.states.push_back(sample.state);
        return true;
    });
    return r;
}

// ------------------------------------------------------------------ restitution
TEST(JointStop, PendulumReboundsToESquaredTimesTheDrop) {
    const Pendulum p;
    const mbd::Model model = mbd::test::scene(p.yaml("restitution: " + g17(p.e)));
    const double t_hit = p.quarter(p.phi0), t_peak = t_hit + p.quarter(p.phi1());
    for (const char* integrator : {"dopri5", "dop853", "cvode"}) {
        const Outcome r = simulate(model, settings(integrator, t_peak, t_peak / 2000, 1e-11));
        ASSERT_EQ(r.result.events.size(), 1u) << integrator;
        const mbd::EventRecord& hit = r.result.events[0];
        EXPECT_EQ(hit.kind, "impact");
        EXPECT_EQ(hit.force, "stop");
        EXPECT_EQ(hit.event, "lower");
        // phidot- from energy: I_O phidot^2 / 2 = m g drop
        const double approach = -std::sqrt(2.0 * p.m * kG * p.drop() / p.inertia());
        const double height = p.l * (1.0 - std::cos(r.states.back().q[2]));
        std::printf("%s: impact at %.15f (closed form %.15f), rate %.12f -> %.12f (closed form %.12f), rebound "
                    "height %.12f, e^2 drop %.12f, %ld events\n",
                    integrator, hit.time, t_hit, hit.rate_before, hit.rate_after, approach, height,
                    p.e * p.e * p.drop(), r.result.stats.events);
        EXPECT_NEAR(hit.time, t_hit, 1e-9) << integrator;
        EXPECT_NEAR(hit.rate_before, approach, 1e-8) << integrator;
        EXPECT_NEAR(hit.rate_after, -p.e * hit.rate_before, 1e-12) << integrator;
        EXPECT_NEAR(height, p.e * p.e * p.drop(), 1e-6) << integrator;
        // the pendulum never passes the stop: no output row beyond it
        double deepest = 0.0;
        for (const mbd::State& s : r.states) deepest = std::min(deepest, s.q[2]);
        EXPECT_GT(deepest, -1e-9) << integrator;
    }
}

// The spatial pendulum (revolute about world y; the stop's angle about the marker's z axis
// is zero at the start and phi0 at the bottom, so `upper: phi0` is the bottom) and a block
// falling a height d on a prismatic guide onto a travel stop (planar and spatial): each
// rebounds to e^2 times its drop. The block's closed forms: impact at sqrt(2 d / g) at the
// speed v = sqrt(2 g d), the peak e v / g later.
TEST(JointStop, SpatialPendulumAndTravelStopsReboundToESquaredTimesTheDrop) {
    const Pendulum p;
    const std::string spatial_pendulum =
        "name: spatial-pendulum-stop\ndimension: spatial\ngravity: [0, 0, -9.81]\n"
        "bodies:\n  - {name: bob, mass: " + g17(p.m) + ", inertia: [" + g17(p.J) + ", " + g17(p.J) + ", " + g17(p.J) +
        "], position: [" + g17(p.l * std::sin(p.phi0)) + ", 0, " + g17(-p.l * std::cos(p.phi0)) + "]}\n"
        "joints:\n  - {name: pivot, type: revolute, bodies: [ground, bob], point: [0, 0, 0], axis: [0, 1, 0]}\n"
        "forces:\n  - {name: stop, type: joint_stop, bodies: [ground, bob], point: [0, 0, 0], axis: [0, 1, 0], "
        "upper: " + g17(p.phi0) + ", restitution: " + g17(p.e) + "}\n";
    {
        const double t_peak = p.quarter(p.phi0) + p.quarter(p.phi1());
        const Outcome r = simulate(mbd::test::scene(spatial_pendulum), settings("dopri5", t_peak, t_peak / 500, 1e-11));
        ASSERT_EQ(r.result.events.size(), 1u);
        EXPECT_EQ(r.result.events[0].event, "upper");
        const double height = p.l + r.states.back().q[2];
        std::printf("spatial pendulum: impact at %.15f (closed form %.15f), rebound height %.12f, e^2 drop %.12f\n",
                    r.result.events[0].time, p.quarter(p.phi0), height, p.e * p.e * p.drop());
        EXPECT_NEAR(r.result.events[0].time, p.quarter(p.phi0), 1e-9);
        EXPECT_NEAR(height, p.e * p.e * p.drop(), 1e-6);
    }
    const double d = 0.3, e = 0.7, v = std::sqrt(2 * kG * d);
    const double t_hit = std::sqrt(2 * d / kG), t_peak = t_hit + e * v / kG;
    for (const char* dimension : {"planar", "spatial"}) {
        const bool planar = std::string(dimension) == "planar";
        const std::string yaml =
            std::string("name: falling-block-stop\ndimension: ") + dimension + "\ngravity: " +
            (planar ? "[0, -9.81]" : "[0, 0, -9.81]") + "\nbodies:\n  - {name: block, mass: 2, inertia: " +
            (planar ? "0.1" : "[0.1, 0.1, 0.1]") + ", position: " + (planar ? "[0.2, 0.3]" : "[0.2, 0, 0.3]") +
            "}\njoints:\n  - {name: guide, type: prismatic, bodies: [ground, block], point: " +
            (planar ? "[0.2, 0], axis: [0, 1]" : "[0.2, 0, 0], axis: [0, 0, 1]") +
            "}\nforces:\n  - {name: stop, type: joint_stop, bodies: [ground, block], coordinate: travel, point: " +
            (planar ? "[0.2, 0], axis: [0, 1]" : "[0.2, 0, 0], axis: [0, 0, 1]") + ", lower: 0, restitution: " + g17(e) +
            "}\n";
        for (const char* integrator : {"dopri5", "dop853", "cvode"}) {
            const Outcome r = simulate(mbd::test::scene(yaml), settings(integrator, t_peak, t_peak / 500, 1e-11));
            ASSERT_EQ(r.result.events.size(), 1u) << dimension << " " << integrator;
            const double height = r.states.back().q[planar ? 1 : 2];
            std::printf("%s travel stop, %s: impact at %.15f (closed form %.15f), rate %.12f (closed form %.12f), "
                        "rebound height %.12f, e^2 drop %.12f\n",
                        dimension, integrator, r.result.events[0].time, t_hit, r.result.events[0].rate_before, -v,
                        height, e * e * d);
            EXPECT_NEAR(r.result.events[0].time, t_hit, 1e-9);
            EXPECT_NEAR(r.result.events[0].rate_before, -v, 1e-8);
            EXPECT_NEAR(height, e * e * d, 1e-6);
        }
    }
}

// Every step the explicit pairs (dopri5, dop853) take ends on the open side of the stop: a step straddling the impact
// would end past it, at a depth of the order of the step times the approach speed.
class StepRecorder final : public mbd::OdeProblem {
public:
    explicit StepRecorder(mbd::OdeProblem& inner) : inner_(inner) {}
    int size() const override { return inner_.size(); }
    void rhs(double t, const Eigen::VectorXd& y, Eigen::VectorXd& ydot) override { inner_.rhs(t, y, ydot); }
    bool project(double t, Eigen::VectorXd& y) override {
        const bool ok = inner_.project(t, y);
        inner_.event_values(t, y, g_);
        step_ends.push_back({t, g_[0]});
        return ok;
    }
    int event_count() const override { return inner_.event_count(); }
    void event_values(double t, const Eigen::VectorXd& y, Eigen::VectorXd& g) override { inner_.event_values(t, y, g); }
    bool handle_events(double t, Eigen::VectorXd& y, const std::vector<int>& crossed, std::vector<int>& side) override {
        event_times.push_back(t);
        return inner_.handle_events(t, y, crossed, side);
    }
    std::vector<std::pair<double, double>> step_ends;  // (t, g)
    std::vector<double> event_times;

private:
    mbd::OdeProblem& inner_;
    Eigen::VectorXd g_;
};

TEST(JointStop, NoStepOfTheExplicitPairsStraddlesAnImpact) {
    for (const char* integrator : {"dopri5", "dop853"}) {
        SCOPED_TRACE(integrator);
        Pendulum p;
        p.e = 0.9;  // several rebounds
        const mbd::Model model = mbd::test::scene(p.yaml("restitution: " + g17(p.e)));
        mbd::ModelSystem system(model);
        mbd::Param node;
        std::shared_ptr<mbd::Formulation> formulation = mbd::test::make_formulation("augmented", node);
        formulation->bind(system, {});
        mbd::State state = system.initial_state();
        system.assemble(state);
        system.consistent_velocities(state);
        mbd::ContactEvents events(system);
        std::vector<mbd::EventRecord> log;
        mbd::ContactProblem contact(*formulation, system, events, log);
        StepRecorder recorder(contact);
        Eigen::VectorXd y;
        formulation->to_ode(state, y);
        mbd::IntegratorSettings s;
        s.tolerance = 1e-9;
        mbd::IntegratorStats stats;
        mbd::make_integrator(integrator, s)->integrate(recorder, 0.0, y, {4.0}, {}, stats);
        ASSERT_GE(recorder.event_times.size(), 3u);
        EXPECT_EQ(stats.events, static_cast<long>(recorder.event_times.size()));
        double deepest = 0.0;
        for (const auto& [t, g] : recorder.step_ends) deepest = std::min(deepest, g);
        // the steps end on the events: each event time is a step end
        for (double te : recorder.event_times) {
            bool found = false;
            for (const auto& [t, g] : recorder.step_ends) found = found || t == te;
            EXPECT_TRUE(found) << te;
        }
        std::printf("%s: %zu steps, %zu impacts, deepest step end %.3e rad\n", integrator, recorder.step_ends.size(),
                    recorder.event_times.size(), deepest);
        // A straddling step would end ~0.1 rad past the stop. The re-taken step ends where its
        // own solution puts it, which differs from the continuous extension the root was found
        // on by the extension's error, a fraction of the tolerance (dop853: 7e-12 rad past).
        EXPECT_GT(deepest, -0.1 * s.tolerance);
        // the impacts: each at the closed-form time after the previous rebound
        double t = p.quarter(p.phi0), amplitude = p.phi0;
        for (size_t k = 0; k < log.size(); ++k) {
            EXPECT_NEAR(log[k].time, t, 1e-7) << k;
            amplitude = std::acos(1.0 - p.e * p.e * (1.0 - std::cos(amplitude)));
            t += 2.0 * p.quarter(amplitude);
        }
    }
}

// ------------------------------------------------------------------ the compliant law
// A wheel (J) turning freely at w0 into a stop at `upper` with F = delta^n (k + c delta').
struct Wheel {
    double J = 0.2, w0 = 3.0, upper = 0.5, k = 400.0, n = 1.5, c = 30.0;
    std::string yaml() const {
        return "name: wheel-stop\ndimension: planar\n"
               "bodies:\n  - {name: wheel, mass: 1, inertia: " + g17(J) + ", angular_velocity: " + g17(w0) + "}\n"
               "joints:\n  - {name: axle, type: revolute, bodies: [ground, wheel], point: [0, 0]}\n"
               "forces:\n  - {name: stop, type: joint_stop, bodies: [ground, wheel], upper: " + g17(upper) +
               ", law: hunt_crossley, stiffness: " + g17(k) + ", exponent: " + g17(n) + ", damping: " + g17(c) +
               "}\n";
    }
    // The contact's own ODE by RK4 from delta = 0, delta' = w0 until delta returns to 0 (the
    // crossing found by a last partial step): the contact's duration and the exit speed.
    void contact(double& duration, double& exit_speed) const {
        auto f = [&](double d, double dd) {
            const double F = d > 0 ? std::pow(d, n) * (k + c * dd) : 0.0;
            return -std::max(F, 0.0) / J;
        };
        double d = 0, v = w0, t = 0;
        const double h = 1e-6;
        for (;;) {
            const double k1d = v, k1v = f(d, v);
            const double k2d = v + 0.5 * h * k1v, k2v = f(d + 0.5 * h * k1d, v + 0.5 * h * k1v);
            const double k3d = v + 0.5 * h * k2v, k3v = f(d + 0.5 * h * k2d, v + 0.5 * h * k2v);
            const double k4d = v + h * k3v, k4v = f(d + h * k3d, v + h * k3v);
            const double dn = d + h / 6 * (k1d + 2 * k2d + 2 * k3d + k4d);
            const double vn = v + h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
            if (dn <= 0.0 && t > 0.0) {
                const double fraction = d / (d - dn);  // linear in the last step: d'' is small there
                duration = t + fraction * h;
                exit_speed = -(v + fraction * (vn - v));
                return;
            }
            d = dn;
            v = vn;
            t += h;
        }
    }
};

TEST(JointStop, HuntCrossleyReboundMatchesTheContactOde) {
    const Wheel w;
    double duration = 0, exit_speed = 0;
    w.contact(duration, exit_speed);
    const mbd::Model model = mbd::test::scene(w.yaml());
    const double t_onset = w.upper / w.w0;
    for (const char* integrator : {"dopri5", "dop853", "cvode"}) {
        const Outcome r = simulate(model, settings(integrator, t_onset + duration + 0.1, 0.01, 1e-11));
        ASSERT_EQ(r.result.events.size(), 2u) << integrator;
        const mbd::EventRecord &onset = r.result.events[0], &release = r.result.events[1];
        EXPECT_EQ(onset.kind, "close");
        EXPECT_EQ(release.kind, "open");
        const double speed = r.states.back().v[2];
        const double lost = 0.5 * w.J * (w.w0 * w.w0 - speed * speed);
        const double lost_ode = 0.5 * w.J * (w.w0 * w.w0 - exit_speed * exit_speed);
        std::printf("%s: onset %.15f (closed form %.15f), release %.12f (ODE %.12f), exit speed %.12f (ODE %.12f), "
                    "energy lost %.12f (ODE %.12f)\n",
                    integrator, onset.time, t_onset, release.time, t_onset + duration, -speed, exit_speed, lost,
                    lost_ode);
        EXPECT_NEAR(onset.time, t_onset, 1e-12) << integrator;
        EXPECT_NEAR(release.time, t_onset + duration, 1e-8) << integrator;
        EXPECT_NEAR(-speed, exit_speed, 1e-7) << integrator;
        EXPECT_NEAR(lost, lost_ode, 1e-7) << integrator;
        EXPECT_GT(lost, 0.1 * 0.5 * w.J * w.w0 * w.w0);  // the damping took a real share
    }
}

// Without damping the compliant law is conservative with the potential k delta^(n+1) / (n + 1):
// through a whole contact (onset, the deepest point, release) the kinetic energy plus that
// potential stays constant, the element's own potential_energy() is that closed form, and the
// body leaves the stop at the speed it came in. A revolute's angle (planar and spatial) and a
// prismatic's travel, each turned or pushed at rate 3 into an upper stop at 0.5.
TEST(JointStop, UndampedCompliantStopConservesEnergyWithItsPotential) {
    const double k = 400.0, n = 1.5, upper = 0.5, rate = 3.0;
    const std::string law = "upper: " + g17(upper) + ", law: hunt_crossley, stiffness: " + g17(k) + ", exponent: " +
                            g17(n) + ", damping: 0}\n";
    struct Case {
        const char* label;
        std::string yaml;
        int coordinate, velocity;  // where s and its rate are in q and v (spatial angle: from p)
        bool spatial_angle;
    };
    const std::vector<Case> cases = {
        {"planar angle",
         "name: wheel-stop\ndimension: planar\nbodies:\n  - {name: wheel, mass: 1, inertia: 0.2, angular_velocity: 3}\n"
         "joints:\n  - {name: axle, type: revolute, bodies: [ground, wheel], point: [0, 0]}\n"
         "forces:\n  - {name: stop, type: joint_stop, bodies: [ground, wheel], " + law,
         2, 2, false},
        {"planar travel",
         "name: block-stop\ndimension: planar\nbodies:\n  - {name: block, mass: 0.2, inertia: 0.1, velocity: [3, 0]}\n"
         "joints:\n  - {name: guide, type: prismatic, bodies: [ground, block], point: [0, 0], axis: [1, 0]}\n"
         "forces:\n  - {name: stop, type: joint_stop, bodies: [ground, block], point: [0, 0], axis: [1, 0], "
         "coordinate: travel, " + law,
         0, 0, false},
        {"spatial angle",
         "name: wheel-stop\ndimension: spatial\nbodies:\n  - {name: wheel, mass: 1, inertia: [0.3, 0.3, 0.2], "
         "angular_velocity: [0, 0, 3]}\n"
         "joints:\n  - {name: axle, type: revolute, bodies: [ground, wheel], point: [0, 0, 0], axis: [0, 0, 1]}\n"
         "forces:\n  - {name: stop, type: joint_stop, bodies: [ground, wheel], point: [0, 0, 0], axis: [0, 0, 1], " + law,
         3, 5, true},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.label);
        const mbd::Model model = mbd::test::scene(c.yaml);
        mbd::ModelSystem system(model);
        const Outcome r = simulate(model, settings("dop853", 0.5, 0.002, 1e-11));
        ASSERT_EQ(r.result.events.size(), 2u);  // onset and release
        double E0 = 0.0, drift = 0.0, potential = 0.0, deepest = 0.0;
        for (const mbd::State& s : r.states) {
            const double coordinate =
                c.spatial_angle ? 2.0 * std::atan2(s.q[c.coordinate + 3], s.q[c.coordinate]) : s.q[c.coordinate];
            const double delta = std::max(coordinate - upper, 0.0);
            const double V = k * std::pow(delta, n + 1) / (n + 1);
            mbd::State copy = s;
            const double E = system.kinetic_energy(copy) + system.potential_energy(copy);
            if (&s == &r.states.front()) E0 = E;
            drift = std::max(drift, std::abs(E - E0));
            potential = std::max(potential, std::abs(system.potential_energy(copy) - V));
            deepest = std::max(deepest, delta);
        }
        const double exit_rate = r.states.back().v[c.velocity];
        std::printf("%s: deepest %.6f past the stop, energy drift %.2e of %.6f, potential error %.2e, exit rate %.12f\n",
                    c.label, deepest, drift, E0, potential, exit_rate);
        EXPECT_GT(deepest, 0.05);
        EXPECT_LT(drift, 2e-9 * E0);  // measured 1.1e-10 to 4.3e-10 J of 0.9 J
        EXPECT_LT(potential, 1e-12 * E0);
        EXPECT_NEAR(exit_rate, -rate, 1e-8);
    }
}

// Restitution with a compliant law: impacts slower than rest_velocity come to rest, and the
// law holds the pendulum on a stop at lower = 0.3 rad, which gravity loads with the moment
// m g l sin(phi): it settles at the static deflection k delta^n = m g l sin(0.3 - delta).
TEST(JointStop, ReboundsDieOutIntoARestingContactHeldByTheLaw) {
    Pendulum p;
    p.e = 0.5;
    p.lower = 0.3;
    const double k = 1e4, n = 1.5;
    const mbd::Model model = mbd::test::scene(
        p.yaml("restitution: 0.5, rest_velocity: 0.05, law: hunt_crossley, stiffness: 1e4, exponent: 1.5, "
               "damping: 5e4"));
    const Outcome r = simulate(model, settings("dopri5", 8.0, 0.01, 1e-10));
    int impacts = 0, rests = 0;
    for (const mbd::EventRecord& e : r.result.events) {
        if (e.kind == "impact") {
            ++impacts;
            EXPECT_NEAR(e.rate_after, -0.5 * e.rate_before, 1e-12);
            EXPECT_GE(0.5 * -e.rate_before, 0.05);  // faster than rest_velocity: a rebound
        }
        if (e.kind == "rest") {
            ++rests;
            EXPECT_LT(0.5 * -e.rate_before, 0.05);
            EXPECT_NEAR(e.rate_after, 0.0, 1e-12);
        }
    }
    const mbd::State& last = r.states.back();
    double delta = 0.0;  // k delta^n = m g l sin(0.3 - delta), by fixed-point iteration (a contraction here)
    for (int i = 0; i < 200; ++i) delta = std::pow(p.m * kG * p.l * std::sin(0.3 - delta) / k, 1.0 / n);
    std::printf("%d impacts, %d rests, %zu events; at rest at %.12f (closed form %.12f), speed %.2e\n", impacts, rests,
                r.result.events.size(), last.q[2], 0.3 - delta, last.v[2]);
    EXPECT_GE(impacts, 4);
    EXPECT_GE(rests, 1);
    EXPECT_NEAR(last.q[2], 0.3 - delta, 1e-6);
    EXPECT_LT(std::abs(last.v[2]), 1e-6);
}

// Without a rest (rest_velocity far below any speed) the rebounds of a falling block come
// ever faster, a geometric series with a finite sum: the events pile up at its limit, and
// the run stops there with an error naming the stop instead of taking events forever.
TEST(JointStop, EventsPilingUpAtOneTimeStopTheRun) {
    const std::string yaml =
        "name: zeno\ndimension: planar\ngravity: [0, -9.81]\n"
        "bodies:\n  - {name: block, mass: 1, inertia: 0.1, position: [0, 0.1]}\n"
        "joints:\n  - {name: guide, type: prismatic, bodies: [ground, block], point: [0, 0], axis: [0, 1]}\n"
        "forces:\n  - {name: stop, type: joint_stop, bodies: [ground, block], coordinate: travel, point: [0, 0], "
        "axis: [0, 1], lower: 0, restitution: 0.5, rest_velocity: 1e-300}\n";
    // the rebounds' flight times 2 e^k v / g sum to the accumulation time (1 + e) / (1 - e) sqrt(2 d / g)
    const double t_limit = 3.0 * std::sqrt(2 * 0.1 / kG);
    for (const char* integrator : {"dopri5", "dop853", "cvode"}) {
        try {
            simulate(mbd::test::scene(yaml), settings(integrator, 2 * t_limit, 0.01, 1e-10));
            ADD_FAILURE() << integrator << ": no error";
        } catch (const mbd::DynamicsError& e) {
            const std::string what = e.what();
            std::printf("%s: stopped at t = %.9f (accumulation time %.9f): %s\n", integrator, e.time(), t_limit,
                        what.c_str());
            // dopri5 and dop853 resolve the rebounds until they pile up; cvode's restarts at order 1 lose
            // the speeds below its tolerance a little earlier, where a touch without approach
            // speed is a rest the stop cannot hold
            EXPECT_TRUE(what.find("events pile up") != std::string::npos ||
                        (std::string(integrator) == "cvode" && what.find("comes to rest") != std::string::npos))
                << what;
            EXPECT_NE(what.find("joint_stop 'stop' (lower)"), std::string::npos) << what;
            EXPECT_NEAR(e.time(), t_limit, std::string(integrator) == "cvode" ? 1e-4 : 1e-6) << integrator;
        }
    }
}

// mbd simulate lists the located events.
TEST(JointStop, SimulateListsTheEvents) {
    const auto r = mbd::test::run_mbd("simulate " + mbd::test::scene_path("examples/force-joint-stop.yaml").string() +
                                      " --t-end 2 --integrator dopri5 --output " +
                                      (mbd::test::scratch("joint-stop") / "out.csv").string());
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("events "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("impact 'stop' (upper) at t = "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("rest 'stop' (upper) at t = "), std::string::npos) << r.out;
}

// ------------------------------------------------------------------ refusals
TEST(JointStop, FixedStepIntegratorsAreRefusedByName) {
    const Pendulum p;
    const mbd::Model model = mbd::test::scene(p.yaml("restitution: 0.5"));
    for (const char* integrator : {"rk4", "euler"}) {
        mbd::SimulationSettings s = settings(integrator, 0.1, 0.01, 1e-6);
        s.integration.step = 1e-3;
        try {
            simulate(model, s);
            ADD_FAILURE() << integrator << ": no error";
        } catch (const mbd::InputError& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find("does not locate events"), std::string::npos) << what;
            EXPECT_NE(what.find("joint_stop 'stop'"), std::string::npos) << what;
            EXPECT_NE(what.find("dopri5, dop853 or cvode"), std::string::npos) << what;
        }
    }
}

std::string error_of(const std::string& yaml) {
    try {
        const mbd::Model model = mbd::test::scene(yaml, "stop.yaml");
        simulate(model, settings("dopri5", 0.01, 0.005, 1e-8));
    } catch (const std::exception& e) {
        return e.what();
    }
    return "";
}

TEST(JointStop, BadInputIsNamedWithItsKeyAndLine) {
    const Pendulum p;
    const struct {
        std::string keys, expected;
    } cases[] = {
        {"upper: -0.5, restitution: 0.5", "'lower' must be below 'upper'"},
        {"restitution: -0.1", "'restitution' must lie in [0, 1]"},
        {"restitution: 1.5", "'restitution' must lie in [0, 1]"},
        {"law: hertz, stiffness: 10", "unknown 'law' 'hertz'"},
        {"law: hunt_crossley", "missing key 'stiffness'"},
        {"law: hunt_crossley, stiffness: 10, exponent: 0.5", "'exponent' must be at least 1"},
        {"stiffness: 10", "'stiffness' belongs to a compliant law"},
        {"restitution: 0", "a plastic stop"},
        {"coordinate: twist, restitution: 0.5", "'coordinate' must be 'angle'"},
        {"damping: 1, restitution: 0.5", "'damping' belongs to a compliant law"},
        {"rest_velocity: 0.1, law: hunt_crossley, stiffness: 5", "'rest_velocity' belongs to impacts"},
    };
    for (const auto& c : cases) {
        const std::string what = error_of(p.yaml(c.keys));
        EXPECT_NE(what.find(c.expected), std::string::npos) << c.keys << ": " << what;
        EXPECT_NE(what.find("stop.yaml:"), std::string::npos) << c.keys << ": " << what;
        EXPECT_NE(what.find("force 'stop'"), std::string::npos) << c.keys << ": " << what;
    }
    // neither law: named, with what to give
    const std::string what = error_of(p.yaml("coordinate: angle"));
    EXPECT_NE(what.find("say how the stop acts"), std::string::npos) << what;
}

TEST(JointStop, ImpactStopStartingPastItsLimitIsRefused) {
    Pendulum p;
    p.phi0 = -0.3;  // below the lower limit 0
    const std::string what = error_of(p.yaml("restitution: 0.5"));
    EXPECT_NE(what.find("starts closed"), std::string::npos) << what;
    EXPECT_NE(what.find("joint_stop 'stop' (lower)"), std::string::npos) << what;
}

// ------------------------------------------------------------------ the plugin check
TEST(JointStop, PassesThePluginCheck) {
    const std::string lib = (mbd::test::build_plugin_dir() / "libmbd_force_joint_stop.so").string();
    for (const char* coordinate : {"angle", "travel"}) {
        const auto r = mbd::test::run_mbd("plugin check " + lib + " --params 'coordinate: " + coordinate +
                                          "' --params 'lower: -0.4' --params 'upper: 0.3'"
                                          " --params 'law: hunt_crossley' --params 'stiffness: 100'"
                                          " --params 'exponent: 1.5' --params 'damping: 2'");
        EXPECT_EQ(r.exit_code, 0) << coordinate << r.out << r.err;
        EXPECT_NE(r.out.find("0 failed"), std::string::npos) << r.out;
        // without damping the law is conservative, and the check compares Q with -dV/dq too
        const auto undamped = mbd::test::run_mbd("plugin check " + lib + " --params 'coordinate: " + coordinate +
                                                 "' --params 'lower: -0.4' --params 'upper: 0.3'"
                                                 " --params 'law: hunt_crossley' --params 'stiffness: 100'"
                                                 " --params 'exponent: 1.5' --params 'damping: 0'");
        EXPECT_EQ(undamped.exit_code, 0) << coordinate << undamped.out << undamped.err;
        EXPECT_NE(undamped.out.find("0 failed"), std::string::npos) << undamped.out;
        EXPECT_NE(undamped.out.find("Q = -dV/dq"), std::string::npos) << undamped.out;
    }
}

}  // namespace
