// Issue 13, item 3: the embedding formulation's closure path (a spanning tree in joint
// coordinates plus the loop-closure rows of the cut joints and drivers, solved by the augmented
// method in joint space; plugins/formulations/articulated_body/loop_closure.hpp). Oracles, none of them
// from the path itself:
//   - the augmented formulation (book Eq. 6.141 in absolute coordinates) at tight tolerance
//     (dopri5, tol 1e-12): positions and every row's multiplier (tree joints, cut joints,
//     drivers) to 1e-8 relative to their size, over a simulated interval;
//   - the conservation of T + V on the conservative four-bar, to the hamiltonian test's bound;
//   - the path really taken: the log line, and y's size = the tree's joint coordinates;
//   - a dead centre (book Sec. 3.9) still stops the run with the named singular configuration;
//   - drivers on tree joints (prescribed motion on the recursive path): the motor torque of a
//     driven pendulum in closed form, and augmented on driven trees.
#include <mbd/model_system.hpp>
#include <mbd/scene.hpp>
#include <mbd/kit/formulation.hpp>
#include <mbd/simulation.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <tuple>
#include <vector>

#include "support/test_support.hpp"

namespace {

using mbd::test::shared_registry;

struct Trace {
    std::vector<mbd::State> states;
    std::vector<Eigen::VectorXd> lambdas;
    std::vector<std::string> messages;
    long steps = 0;
};

Trace simulate(const mbd::Model& model, const std::string& formulation, double tol, double t_end, double step) {
    mbd::SimulationSettings s = mbd::test::adaptive_run(formulation, "dopri5", tol, t_end, step);
    s.reactions = true;
    Trace out;
    s.messages = mbd::MessageLog([&out](const std::string& line) { out.messages.push_back(line); });
    const mbd::SimulationResult r = mbd::simulate(model, shared_registry(), s, [&](const mbd::SimulationSample& sample) {
        out.states.push_back(sample.state);
        out.lambdas.push_back(sample.lambda ? *sample.lambda : Eigen::VectorXd());
        return true;
    });
    out.steps = r.stats.steps;
    return out;
}

bool logged(const Trace& r, const std::string& text) {
    return std::any_of(r.messages.begin(), r.messages.end(),
                       [&](const std::string& m) { return m.find(text) != std::string::npos; });
}

struct Case {
    const char* scene;
    double t_end;
    int joint_coordinates;  // the tree's: ode_size = 2 x this for 1-DOF joints
    bool forced = false;    // path: closure (a driven tree, which path: auto runs on the recursive path)
};

// the scene, with `path: closure` when the case forces it
mbd::Model load_case(const Case& c) {
    if (!c.forced) return mbd::test::load(c.scene);
    const std::string text = mbd::test::read_text(mbd::test::scene_path(c.scene));
    return mbd::load_scene_text(text + "\nformulation: {type: embedding, path: closure}\n", c.scene, shared_registry());
}

// car axis: pivot and left_guide are tree edges, the right wheel a free root (3), the bump row
// and the distance joint close it; flyball: four joints in a tree, the motor's row closes it
// (forced: path auto prescribes the motor's motion on the recursive path, PrescribedMotion below);
// four-bars: every revolute but the cut; slider crank: three revolutes, the guide is cut.
const Case kCases[] = {
    {"bench/car-axis.yaml", 1.0, 5},
    {"bench/a05-flyball.yaml", 0.02, 4, true},  // stiff: 0.02 s holds a period of its springs' mode
    {"bench/a02-four-bar-2.yaml", 0.3, 5},
    {"dynamics/four-bar-conservative.yaml", 1.0, 3},
    {"dynamics/slider-crank.yaml", 1.0, 3},
};

class LoopClosure : public ::testing::TestWithParam<Case> {};

TEST_P(LoopClosure, TakesTheClosurePathInJointCoordinates) {
    const Case c = GetParam();
    const mbd::Model model = load_case(c);
    mbd::ModelSystem system(model);
    mbd::Param node;
    auto f = c.forced ? mbd::test::make_formulation("embedding", node, {{"path", "closure"}})
                      : mbd::test::make_formulation("embedding", node);
    std::vector<std::string> log;
    mbd::FormulationOptions options;
    options.log = mbd::MessageLog([&log](const std::string& line) { log.push_back(line); });
    f->bind(system, options);
    ASSERT_FALSE(log.empty());
    EXPECT_NE(log.front().find("embedding: closure path"), std::string::npos) << log.front();
    EXPECT_EQ(f->ode_size(), 2 * c.joint_coordinates) << c.scene;
    EXPECT_LT(f->ode_size(), system.nq() + system.nv());
}

// Positions and multipliers of every row on the embedding path named `path` against augmented,
// both at tol 1e-12 (dopri5), to 1e-8 of their size.
void expect_agreement_with_augmented(const mbd::Model& model, const std::string& label, double t_end,
                                     const std::string& path) {
    const double tol = 1e-12, sample = t_end / 50;
    const Trace embedding = simulate(model, "embedding", tol, t_end, sample);
    const Trace reference = simulate(model, "augmented", tol, t_end, sample);
    ASSERT_TRUE(logged(embedding, "embedding: " + path)) << label;
    ASSERT_EQ(embedding.states.size(), reference.states.size());
    double dq = 0.0, dl = 0.0, q_scale = 1.0, l_scale = 1.0;
    for (size_t i = 0; i < embedding.states.size(); ++i) {
        dq = std::max(dq, mbd::test::position_difference(model, embedding.states[i].q, reference.states[i].q));
        ASSERT_EQ(embedding.lambdas[i].size(), reference.lambdas[i].size());
        dl = std::max(dl, (embedding.lambdas[i] - reference.lambdas[i]).lpNorm<Eigen::Infinity>());
        q_scale = std::max(q_scale, reference.states[i].q.lpNorm<Eigen::Infinity>());
        l_scale = std::max(l_scale, reference.lambdas[i].lpNorm<Eigen::Infinity>());
    }
    std::printf("%-38s %s vs augmented, dopri5 tol 1e-12 over [0, %g]: |dq| %.2e (scale %.3g), |dlambda| %.2e "
                "(scale %.3g); steps %ld vs %ld\n",
                label.c_str(), path.c_str(), t_end, dq, q_scale, dl, l_scale, embedding.steps, reference.steps);
    EXPECT_LT(dq, 1e-8 * q_scale) << label;
    EXPECT_LT(dl, 1e-8 * l_scale) << label;
}

TEST_P(LoopClosure, AgreesWithAugmentedInPositionsAndMultipliers) {
    const Case c = GetParam();
    expect_agreement_with_augmented(load_case(c), c.scene, c.t_end, "closure path");
}

INSTANTIATE_TEST_SUITE_P(Scenes, LoopClosure, ::testing::ValuesIn(kCases), [](const auto& info) {
    std::string name = info.param.scene;
    name = name.substr(0, name.size() - 5);
    for (char& ch : name)
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
    return name;
});

// T + V on the conservative four-bar over 10 s (dopri5, tol 1e-12): the bound of the
// hamiltonian formulation's test (test_hamiltonian.cpp), and no worse than augmented's.
TEST(LoopClosureEnergy, ConservesEnergyOnTheConservativeFourBar) {
    const mbd::Model model = mbd::test::load("dynamics/four-bar-conservative.yaml");
    mbd::ModelSystem system(model);
    double drift[2] = {0.0, 0.0}, span = 0.0;
    const char* names[2] = {"embedding", "augmented"};
    for (int k = 0; k < 2; ++k) {
        const Trace r = simulate(model, names[k], 1e-12, 10.0, 0.01);
        if (k == 0) ASSERT_TRUE(logged(r, "embedding: closure path"));
        ASSERT_EQ(r.states.size(), 1001u);
        auto energy = [&](const mbd::State& s) { return system.kinetic_energy(s) + system.potential_energy(mbd::State(s)); };
        const double E0 = energy(r.states.front()), T0 = system.kinetic_energy(r.states.front());
        for (const mbd::State& s : r.states) {
            drift[k] = std::max(drift[k], std::abs(energy(s) - E0));
            span = std::max(span, std::abs(system.kinetic_energy(s) - T0));
        }
    }
    std::printf("four-bar-conservative 10 s, dopri5 tol 1e-12: max |E - E0| closure path %.3e, augmented %.3e\n", drift[0],
                drift[1]);
    EXPECT_GT(span, 0.1);
    EXPECT_LT(drift[0], 1e-8);
    EXPECT_LT(drift[0], 10 * std::max(drift[1], 1e-12));
}

// The slider crank driven through its dead centre (book Sec. 3.9) on the closure path: the run
// stops at t ~ 0.5 s with the named rank drop, not a silent jump to the other branch.
TEST(LoopClosureSingularity, DeadCentreStopsWithANamedSingularConfiguration) {
    const mbd::Model model = mbd::test::load("extreme/slider-crank-dead-centre.yaml");
    std::vector<std::string> log;
    mbd::SimulationSettings s = mbd::test::adaptive_run("embedding", "dopri5", 1e-8, 1.0, 0.01);
    s.messages = mbd::MessageLog([&log](const std::string& line) { log.push_back(line); });
    try {
        mbd::simulate(model, shared_registry(), s);
        ADD_FAILURE() << "the run passed the dead centre";
    } catch (const mbd::DynamicsError& e) {
        std::printf("dead centre on the closure path: t = %.4f: %s\n", e.time(), e.what());
        EXPECT_NE(std::string(e.what()).find("lost rank"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("dead centre"), std::string::npos) << e.what();
        EXPECT_NEAR(e.time(), 0.5, 0.05);
    }
    ASSERT_FALSE(log.empty());
    EXPECT_NE(log.front().find("embedding: closure path"), std::string::npos) << log.front();
}

// The parallelogram chain of A02 (N = 40) reaches its flat position at t ~ 0.72 s, where the 40
// loops' rows become dependent (mobility 1 -> 41). The closure path (like augmented) does not
// pass it: it must stop there with a named singular configuration, and up to the stop it must
// conserve T + V (no silent jump to another branch; a jump lost ~100% of the energy).
TEST(LoopClosureSingularity, ParallelogramFlatPositionStopsByNameWithoutABranchJump) {
    const mbd::Model model = mbd::test::load("bench/a02-four-bar-40.yaml");
    mbd::ModelSystem system(model);
    mbd::SimulationSettings s = mbd::test::adaptive_run("embedding", "dopri5", 1e-10, 1.0, 0.01);
    std::vector<std::string> log;
    s.messages = mbd::MessageLog([&log](const std::string& line) { log.push_back(line); });
    std::vector<mbd::State> states;
    try {
        mbd::simulate(model, shared_registry(), s, [&](const mbd::SimulationSample& sample) {
            states.push_back(sample.state);
            return true;
        });
        ADD_FAILURE() << "the closure path passed the flat position";
    } catch (const mbd::DynamicsError& e) {
        std::printf("A02-40 on the closure path: t = %.4f: %.200s...\n", e.time(), e.what());
        EXPECT_NE(std::string(e.what()).find("singular configuration"), std::string::npos) << e.what();
        EXPECT_NEAR(e.time(), 0.72, 0.03);
    }
    ASSERT_FALSE(log.empty());
    EXPECT_NE(log.front().find("embedding: closure path"), std::string::npos) << log.front();
    ASSERT_GT(states.size(), 60u);
    const double E0 = system.kinetic_energy(states.front()) + system.potential_energy(states.front());
    double drift = 0.0;
    for (mbd::State& st : states) drift = std::max(drift, std::abs(system.kinetic_energy(st) + system.potential_energy(st) - E0));
    std::printf("A02-40: max |E - E0| up to the stop %.3e J (E0 %.1f J)\n", drift, E0);
    EXPECT_LT(drift, 1e-6 * std::abs(E0));
}

// Forced on a tree (no closure rows: `path: closure`), the path reduces to the recursive one.
TEST(LoopClosurePath, ForcedOnATreeMatchesTheRecursivePath) {
    const std::string text = mbd::test::read_text(mbd::test::scene_path("dynamics/heavy-top.yaml"));
    const mbd::Model forced =
        mbd::load_scene_text(text + "\nformulation: {type: embedding, path: closure}\n", "heavy-top.yaml", shared_registry());
    const mbd::Model plain = mbd::test::load("dynamics/heavy-top.yaml");
    const Trace closure = simulate(forced, "embedding", 1e-12, 1.0, 0.1);
    const Trace recursive = simulate(plain, "embedding", 1e-12, 1.0, 0.1);
    ASSERT_TRUE(logged(closure, "embedding: closure path"));
    ASSERT_TRUE(logged(recursive, "embedding: recursive path"));
    ASSERT_EQ(closure.states.size(), recursive.states.size());
    double dq = 0.0, dl = 0.0;
    for (size_t i = 0; i < closure.states.size(); ++i) {
        dq = std::max(dq, mbd::test::position_difference(forced, closure.states[i].q, recursive.states[i].q));
        dl = std::max(dl, (closure.lambdas[i] - recursive.lambdas[i]).lpNorm<Eigen::Infinity>());
    }
    std::printf("heavy top, closure (forced) vs recursive, tol 1e-12 over 1 s: |dq| %.2e, |dlambda| %.2e\n", dq, dl);
    EXPECT_LT(dq, 1e-9);
    EXPECT_LT(dl, 1e-7);
}

// A four-bar in the plane y = 0.11566 (cassie's plantar loop, issue 37), its pins along y, closed
// by a spherical joint, its bodies' axes turned: the ball's y row is dependent (every hinge is
// parallel to y) and, through the turned axes, rounding noise (~1e-17) rather than exactly 0, in
// its Jacobian row and its residual. Unit-diagonal equilibration of S made that row a
// healthy-looking unit row, so the projection divided the noise by ~1e-17: this scene stopped at
// t = 7e-10 with a false "singular configuration", and the imported cassie silently started up to
// 0.45 rad away from its scene (joint_space_saddle.hpp now takes such a row as dependent). The
// start must be the scene's, the y row named as dropped, the motion augmented's.
TEST(LoopClosurePath, PlanarLoopClosedByABallOffTheOriginKeepsItsStart) {
    const std::string text = R"(name: four-bar-closed-by-a-ball
dimension: spatial
gravity: [0, 0, -9.81]
bodies:
  - {name: crank, mass: 1.0, inertia: [0.0005, 0.004, 0.004], position: [0.1, 0.11566, 0], orientation: {axis: [0.3, 0.5, 0.8], angle: 0.7}, velocity: [0, 0, -0.3], angular_velocity: [0, 3, 0]}
  - {name: coupler, mass: 1.5, inertia: [0.012, 0.015, 0.005], position: [0.375, 0.11566, 0.2], orientation: {axis: [-0.6, 0.2, 0.4], angle: 1.9}, velocity: [-0.3, 0, -0.3375], angular_velocity: [0, -1.5, 0]}
  - {name: rocker, mass: 0.8, inertia: [0.007, 0.008, 0.002], position: [0.575, 0.11566, 0.2], orientation: {axis: [0.1, -0.9, 0.3], angle: 2.6}, velocity: [-0.3, 0, -0.0375], angular_velocity: [0, -1.5, 0]}
joints:
  - {name: O, type: revolute, bodies: [ground, crank], point: [0, 0.11566, 0], axis: [0, 1, 0]}
  - {name: A, type: revolute, bodies: [crank, coupler], point: [0.2, 0.11566, 0], axis: [0, 1, 0]}
  - {name: C, type: revolute, bodies: [ground, rocker], point: [0.6, 0.11566, 0], axis: [0, 1, 0]}
  - {name: B, type: spherical, bodies: [coupler, rocker], point: [0.55, 0.11566, 0.4]}
)";
    const mbd::Model model = mbd::load_scene_text(text, "four-bar-closed-by-a-ball.yaml", shared_registry());
    const Trace closure = simulate(model, "embedding", 1e-12, 1.0, 0.02);
    const Trace reference = simulate(model, "augmented", 1e-12, 1.0, 0.02);
    ASSERT_TRUE(logged(closure, "embedding: closure path"));
    EXPECT_TRUE(logged(closure, "redundant constraint row dropped: joint 'B' (y)"));
    ASSERT_EQ(closure.states.size(), reference.states.size());
    ASSERT_FALSE(closure.states.empty());
    const double start = mbd::test::position_difference(model, closure.states[0].q, model.initial_state().q);
    double dq = 0.0, swing = 0.0;
    for (size_t i = 0; i < closure.states.size(); ++i) {
        dq = std::max(dq, mbd::test::position_difference(model, closure.states[i].q, reference.states[i].q));
        swing = std::max(swing, (reference.states[i].q - reference.states[0].q).lpNorm<Eigen::Infinity>());
    }
    std::printf("four-bar closed by a ball at y = 0.11566: closure path's start off the scene's by %.2e; "
                "against augmented over 1 s %.2e (motion %.3g)\n", start, dq, swing);
    EXPECT_LT(start, 1e-12);
    EXPECT_LT(dq, 1e-8);
    EXPECT_GT(swing, 0.1);
}

// --- Driven tree joints: prescribed motion on the recursive path -------------------------------
// A driver on a tree joint of one freedom prescribes it (articulated_body.hpp): the ODE keeps the
// other joints' coordinates, the sweeps take the driven udot as known, and the driver's multiplier
// comes from the force across the joint.

// A rod pinned to the ground, its pin's coordinate driven: s = 0.4 sin 3t. About the pin,
// (J + m a^2) theta'' = tau - m g a cos(theta): the motor torque is a closed form, and with
// Q_c = -J^T lambda the driver's multiplier is lambda = -tau / (d s / d theta). The pin listed
// both ways (the edge's coordinate then runs against the driver's or with it).
TEST(PrescribedMotion, DrivenPendulumNeedsTheClosedFormTorque) {
    const double m = 2.0, J = 0.3, a = 0.5, g = 9.81, A = 0.4, w = 3.0;
    for (const char* bodies : {"[ground, rod]", "[rod, ground]"}) {
        const mbd::Model model = mbd::test::scene(
            std::string("dimension: planar\ngravity: [0, -9.81]\nbodies:\n"
                        "  - {name: rod, mass: 2, inertia: 0.3, position: [0.5, 0], angle: 0}\n"
                        "joints:\n  - {name: pin, type: revolute, bodies: ") +
            bodies +
            ", point: [0, 0]}\n"
            "drivers:\n  - {name: swing, joint: pin, motion: {type: harmonic, amplitude: 0.4, frequency: 3}}\n");
        mbd::ModelSystem system(model);
        mbd::Param node;
        auto f = mbd::test::make_formulation("embedding", node);
        f->bind(system, mbd::FormulationOptions{});
        EXPECT_EQ(f->ode_size(), 0) << "every motion is prescribed";
        for (const char* integrator : {"dopri5", "cvode"}) {
            mbd::SimulationSettings s = mbd::test::adaptive_run("embedding", integrator, 1e-10, 2.0, 0.05);
            s.reactions = true;
            std::vector<std::string> log;
            s.messages = mbd::MessageLog([&log](const std::string& line) { log.push_back(line); });
            double dtheta = 0.0, dtau = 0.0;
            int samples = 0;
            mbd::simulate(model, shared_registry(), s, [&](const mbd::SimulationSample& sample) {
                // the pin's coordinate s is +-theta as the pin lists the rod second or first: theta = s f(t)
                mbd::ConstraintValues cv;
                system.constraints(sample.state, cv, true);
                const double ds_dtheta = cv.J.coeff(2, 2);  // the driver's row (after the pin's two) on the rod's angle
                const double t = sample.state.t, theta = ds_dtheta * A * std::sin(w * t);
                const double acc = -ds_dtheta * A * w * w * std::sin(w * t);
                const double tau = (J + m * a * a) * acc + m * g * a * std::cos(theta);
                dtheta = std::max(dtheta, std::abs(sample.state.q[2] - theta));
                dtau = std::max(dtau, std::abs((*sample.lambda)[2] + tau / ds_dtheta));
                ++samples;
                return true;
            });
            ASSERT_FALSE(log.empty());
            EXPECT_NE(log.back().find("1 of them driven (prescribed motion)"), std::string::npos) << log.back();
            std::printf("driven pendulum, pin %s, %s: max |theta - closed form| %.2e, |lambda + tau / s'| %.2e (%d samples)\n",
                        bodies, integrator, dtheta, dtau, samples);
            EXPECT_EQ(samples, 41);
            EXPECT_LT(dtheta, 1e-12);
            EXPECT_LT(dtau, 1e-9);  // tau is up to 14 N m
        }
    }
}

// The flyball (its shaft's motor on a tree of four joints), and a cart driven along its guide
// (listed ground-last) carrying a free double pendulum: every row's multiplier and the positions
// against augmented, and y holds only the free joints' coordinates and speeds.
TEST(PrescribedMotion, DrivenTreesAgreeWithAugmented) {
    const mbd::Model flyball = mbd::test::load("bench/a05-flyball.yaml");
    const mbd::Model cart = mbd::test::scene(
        "dimension: planar\ngravity: [0, -9.81]\nbodies:\n"
        "  - {name: cart, mass: 3, inertia: 0.05, position: [0, 0], angle: 0}\n"
        "  - {name: upper, mass: 1, inertia: 0.02, position: [0.3, 0], angle: 0}\n"
        "  - {name: lower, mass: 0.5, inertia: 0.01, position: [0.8, 0.1], angle: 0.4636476090008061}\n"
        "joints:\n"
        "  - {name: guide, type: prismatic, bodies: [cart, ground], point: [0, 0], axis: [1, 0]}\n"
        "  - {name: shoulder, type: revolute, bodies: [cart, upper], point: [0, 0]}\n"
        "  - {name: elbow, type: revolute, bodies: [upper, lower], point: [0.6, 0]}\n"
        "drivers:\n  - {name: shake, joint: guide, motion: {type: harmonic, amplitude: 0.2, frequency: 5}}\n");
    // (the flyball's stiff springs cost ~30,000 steps per second at tol 1e-12: a short interval,
    // 0.04 s, over two periods of their 400 rad/s mode)
    for (const auto& [model, label, free_joints, t_end] : {std::tuple{&flyball, "bench/a05-flyball.yaml", 3, 0.04},
                                                           std::tuple{&cart, "driven cart, double pendulum", 2, 0.5}}) {
        mbd::ModelSystem system(*model);
        mbd::Param node;
        auto f = mbd::test::make_formulation("embedding", node);
        f->bind(system, mbd::FormulationOptions{});
        EXPECT_EQ(f->ode_size(), 2 * free_joints) << label;
        expect_agreement_with_augmented(*model, label, t_end, "recursive path");
    }
}

}  // namespace
