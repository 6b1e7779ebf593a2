// A driver on a joint at a flexible body (issue 40): its row is mapped onto the body's coordinates
// by the chain rule of the joint's own rows (J = J_f G, gamma = gamma_f - J_f a; sdk body.hpp). A
// stiff ANCF cable (EI = 1e3, EA = 1e6, rho A = 1, L = 1, 2 elements: a few seconds under the sanitizers) is held at its root only by
// a revolute joint to the ground whose angle a driver prescribes, theta(t) a quintic smooth step
// from 0 to 1 rad over [0, 0.5] s, under gravity. Oracles, computed in the test:
// - the root's material frame turns by theta(t) (the root tangent's angle) and stays at the pin;
// - the tip follows the rigid arm L (cos theta, sin theta) within the static bending estimate:
//   the transverse loads rho A (alpha_max x + g) bend a cantilever by 11 rho A alpha_max L^4 /
//   (120 EI) + rho A g L^4 / (8 EI) (both twice over: the loads come on at once and the beam
//   vibrates about them), and the centripetal load stretches it by rho A omega_max^2 L^3 / (3 EA);
// - the motor's torque on the cable (the driver's reaction, mbd/reactions.hpp driver_reactions) is dH/dt - M_g about the pin: H the
//   angular momentum and M_g gravity's moment, both integrated over the cable's mass from its
//   material points (4-point Gauss-Legendre per element), dH/dt by central differences.
// - `mbd statics` holds the arm level with the motor's torque w L^2 / 2 (less the bent arm's
//   shortening).
// Only the augmented formulation takes flexible bodies (docs/formulations.md), with explicit
// integrators: dopri5 here.
#include "support/mass_points.hpp"
#include "support/sampled_run.hpp"
#include "support/test_support.hpp"

#include <mbd/model_system.hpp>
#include <mbd/reactions.hpp>
#include <mbd/sdk/body.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace mbd {
namespace {

constexpr double kG = 9.81, kEI = 1e3, kEA = 1e6, kRhoA = 1.0, kL = 1.0, kTheta1 = 1.0, kT1 = 0.5;
constexpr int kElements = 2;

const std::string kScene =
    "dimension: planar\ngravity: [0, -9.81]\nflexible_bodies:\n"
    "  - {name: arm, type: ancf_cable, from: [0, 0], to: [1, 0], elements: 2, modulus: 1.0e7, area: 0.1, "
    "second_moment: 1.0e-4, density: 10.0}\n"
    "joints:\n  - {name: hub, type: revolute, bodies: [ground, {body: arm, node: 0}]}\n"
    "drivers:\n  - {name: motor, joint: hub, motion: {type: smooth_step, t0: 0, t1: 0.5, from: 0, to: 1.0}}\n";

// theta(t) = theta1 (10 s^3 - 15 s^4 + 6 s^5), s = t / t1, held at theta1 after t1
double theta(double t) {
    const double s = std::min(t / kT1, 1.0);
    return kTheta1 * s * s * s * (10 - 15 * s + 6 * s * s);
}

constexpr double kEnd = 0.6, kStep = 2.5e-4;

struct Sampled {
    Model model;
    std::vector<State> states;
    std::vector<Eigen::VectorXd> lambda;  // the multipliers: the joint's rows, then the driver's
    test::SampledRun table;
};

// One run for both tests (kEnd s sampled every kStep s, with the multipliers).
const Sampled& run() {
    static const Sampled out = [] {
        Sampled s{test::scene(kScene), {}, {}, {}};
        SimulationSettings settings = test::adaptive_run("augmented", "dopri5", 1e-9, kEnd, kStep);
        settings.reactions = true;
        const SimulationResult result = simulate(s.model, test::shared_registry(), settings, [&](const SimulationSample& x) {
            s.states.push_back(x.state);
            s.lambda.push_back(*x.lambda);
            s.table.rows.push_back(*x.row);
            return true;
        });
        s.table.columns = result.columns;
        return s;
    }();
    return out;
}

// The cable's angular momentum about the pin and gravity's moment there (z components), over its
// mass from the material points at arc length x (4-point Gauss-Legendre per element).
struct Moments {
    double H = 0.0, gravity = 0.0;
};

Moments moments(const FlexibleBodyInstance& f, const State& s) {
    Moments out;
    test::for_each_mass_point(f, s, kElements, kL, kRhoA, [&](double dm, const MaterialPoint& p) {
        out.H += dm * (p.r.x() * p.rdot.y() - p.r.y() * p.rdot.x());
        out.gravity += -kG * dm * p.r.x();  // r x (0, -g dm)
    });
    return out;
}

TEST(FlexibleDrivers, TheRootFollowsTheDriverAndAStiffArmTurnsLikeARigidOne) {
    const Sampled& s = run();
    const FlexibleBodyInstance& f = s.model.flexible_bodies.at(0);
    ASSERT_EQ(s.states.size(), static_cast<size_t>(std::lround(kEnd / kStep)) + 1);
    const std::vector<double> root = f.body->node_parameters(0);
    double angle = 0.0, pin = 0.0, tip = 0.0;
    for (size_t r = 0; r < s.states.size(); ++r) {
        const State& state = s.states[r];
        MaterialFrame frame;
        f.body->frame(state.q.segment(f.offset, f.size), state.v.segment(f.v_offset, f.size), root.data(), frame);
        angle = std::max(angle, std::abs(frame.planar.theta - theta(state.t)));
        pin = std::max(pin, frame.planar.R.norm());
        const double th = theta(state.t);
        tip = std::max(tip, std::hypot(s.table.at(r, "arm.node2.x") - kL * std::cos(th),
                                       s.table.at(r, "arm.node2.y") - kL * std::sin(th)));
    }
    const double alpha_max = kTheta1 / (kT1 * kT1) * 10.0 / std::sqrt(3.0);  // the quintic's largest |theta''|
    const double omega_max = kTheta1 / kT1 * 15.0 / 8.0;                     // and |theta'| (at s = 1/2)
    const double bending = 2 * (11 * kRhoA * alpha_max * std::pow(kL, 4) / (120 * kEI) +
                                kRhoA * kG * std::pow(kL, 4) / (8 * kEI));
    const double stretch = kRhoA * omega_max * omega_max * std::pow(kL, 3) / (3 * kEA);
    std::printf("root angle - theta(t) %.3g rad, root off the pin %.3g m; tip off the rigid arm %.4g m (bound %.4g m); "
                "final tip (%.6f, %.6f)\n", angle, pin, tip, bending + stretch,
                s.table.at(s.states.size() - 1, "arm.node2.x"), s.table.at(s.states.size() - 1, "arm.node2.y"));
    EXPECT_LT(angle, 1e-8);
    EXPECT_LT(pin, 1e-8);
    EXPECT_LT(tip, bending + stretch);
    // it turned: the tip is near (cos 1, sin 1) at the end, not hanging from the pin
    EXPECT_GT(s.table.at(s.states.size() - 1, "arm.node2.y"), 0.8);
}

TEST(FlexibleDrivers, TheMotorsTorqueIsTheRateOfAngularMomentumLessGravitysMoment) {
    const Sampled& s = run();
    const FlexibleBodyInstance& f = s.model.flexible_bodies.at(0);
    ModelSystem system(s.model);
    std::vector<Moments> m;
    for (const State& state : s.states) m.push_back(moments(f, state));
    double worst = 0.0, largest = 0.0;
    for (size_t r = 1; r + 1 < s.states.size(); ++r) {
        const std::vector<JointReaction> motor = driver_reactions(system, s.states[r], s.lambda[r]);
        ASSERT_EQ(motor.size(), 1u);
        ASSERT_TRUE(motor[0].on.at(1).material_frame) << "the motor's effort on the cable's root frame";
        const double dH = (m[r + 1].H - m[r - 1].H) / (2 * kStep);
        const double expected = dH - m[r].gravity;
        worst = std::max(worst, std::abs(motor[0].on[1].torque.z() - expected));
        largest = std::max(largest, std::abs(expected));
    }
    std::printf("motor torque against dH/dt - M_g: largest difference %.3g N m of up to %.4g N m\n", worst, largest);
    EXPECT_GT(largest, 0.5 * kRhoA * kG * kL * kL / 2);  // at least half of holding the arm level
    EXPECT_LT(worst, 1e-3 * largest);
}

TEST(FlexibleDrivers, MbdStaticsHoldsTheArmLevelWithTheMotorsTorque) {
    // `mbd statics` at t = 0 (theta = 0): the motor holds the arm level against its weight
    // w = rho A g. Its effort is the weight's moment g int x dm = w L^2 / 2 less w int u ds, u the
    // shortening of the bent arm's projection (1/2 int w'^2 <= L theta_tip^2 / 2 with theta_tip =
    // w L^3 / (6 EI)); the hub carries the weight w L and no torque. The driver's load on the
    // arm's root frame (`load`, System::driver_material_frame) is the same torque.
    const std::filesystem::path dir = test::scratch("flexible_driver_statics");
    const std::filesystem::path scene = test::write_text(dir / "arm.yaml", kScene);
    const test::CommandResult r = test::run_mbd("statics '" + scene.string() + "' --json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    const double w = kRhoA * kG, theta_tip = w * std::pow(kL, 3) / (6 * kEI);
    const double shortening = w * kL * kL * theta_tip * theta_tip / 2;
    const double effort = j["drivers"]["motor"]["effort"], load = j["drivers"]["motor"]["load"]["tz"];
    std::printf("motor effort %.10g N m against w L^2 / 2 = %.10g (bound %.3g); its load on the frame %.10g; hub "
                "F_y %.10g, T %.3g\n", effort, w * kL * kL / 2, shortening, load, j["reactions"]["hub"]["fy"].get<double>(),
                j["reactions"]["hub"]["tz"].get<double>());
    EXPECT_TRUE(j["converged"].get<bool>());
    EXPECT_LE(effort, w * kL * kL / 2 + 1e-9);
    EXPECT_GE(effort, w * kL * kL / 2 - shortening);
    EXPECT_NEAR(load, effort, 1e-9 * effort);
    EXPECT_NEAR(j["reactions"]["hub"]["fy"].get<double>(), w * kL, 1e-9);
    EXPECT_NEAR(j["reactions"]["hub"]["tz"].get<double>(), 0.0, 1e-9);
}

}  // namespace
}  // namespace mbd
