// Force elements attached to points of flexible bodies (`{body: NAME, node: K}` / `{body: NAME,
// at: xi}` in a force's `body` or `bodies`): the element's force on the material frame, Q_f, acts
// on the body's coordinates as G^T Q_f (core/src/evaluation/flexible_forces.cpp). Oracles: the
// Hermite shape functions of the ANCF cable written out here (a point force F at x acts as
// S(x)^T F), the second derivatives of the potential energy by central differences (a spring's
// stiffness), the damper's closed-form velocity Jacobian, conservation of linear momentum and of
// energy between a cable and a free rigid body joined by a spring, and the Euler-Bernoulli tip
// deflection P L^3 / (3 EI) of a cantilever under a small tip load (equilibrium by the test's
// own Newton iteration on the engine's forces and constraints).
#include "support/input_files.hpp"
#include "support/newton_equilibrium.hpp"
#include "support/sanitizer_build.hpp"
#include "support/test_support.hpp"

#include <mbd/model_system.hpp>
#include <mbd/simulation.hpp>

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

namespace mbd {
namespace {

// A planar cable from (0, 0) to (1, 0) in 4 elements: EA = 1e4 N, EI = 10 N m^2, rho A = 1 kg/m.
constexpr int kElements = 4;
constexpr double kLength = 1.0, kEI = 10.0;
const std::string kCable =
    "dimension: planar\nflexible_bodies:\n"
    "  - {name: rope, type: ancf_cable, from: [0, 0], to: [1, 0], elements: 4, modulus: 1.0e4, area: 1.0, "
    "second_moment: 1.0e-3, density: 1.0}\n";

// The cable's generalized force of a force F at arc length x (its coordinates node by node
// [r (x, y), r' (x, y)]): S(x)^T F with the cubic Hermite shapes of the element holding x.
Eigen::VectorXd hermite_force(double x, const Vec2& F) {
    const double le = kLength / kElements;
    const int e = std::min(kElements - 1, static_cast<int>(x / le));
    const double s = x / le - e;
    const double h[4] = {1 - 3 * s * s + 2 * s * s * s, le * (s - 2 * s * s + s * s * s), 3 * s * s - 2 * s * s * s,
                         le * (-s * s + s * s * s)};
    Eigen::VectorXd Q = Eigen::VectorXd::Zero(4 * (kElements + 1));
    for (int k = 0; k < 4; ++k) Q.segment<2>(4 * e + 2 * k) = h[k] * F;
    return Q;
}

TEST(FlexibleForces, APointForceAtAMaterialPointActsThroughTheHermiteShapes) {
    const Vec2 F(0.3, -2.0);
    const Model unloaded = test::scene(kCable);
    for (const std::string& point : {"{body: rope, at: 0.6}", "{body: rope, at: 0.1}", "{body: rope, node: 4}"}) {
        const Model model = test::scene(kCable + "forces:\n  - {name: push, type: point_force, body: " + point +
                                        ", force: [0.3, -2]}\n");
        ModelSystem system(model), unloaded_system(unloaded);
        const State state = system.initial_state();
        Eigen::VectorXd Q, Q_unloaded;
        // the load alone: less the cable's own forces at the same state (its straight mesh's
        // round-off strain gives elastic forces of EA 1e-16 = 1e-12 N)
        system.generalized_forces(state, Q);
        unloaded_system.generalized_forces(state, Q_unloaded);
        Q -= Q_unloaded;
        const double x = point.find("node") != std::string::npos ? 1.0 : std::stod(point.substr(point.find("at:") + 3));
        const Eigen::VectorXd expected = hermite_force(x, F);
        EXPECT_LT((Q - expected).cwiseAbs().maxCoeff(), 1e-14) << point << "\n" << Q.transpose();
    }
}

// A dead load at a material point is conservative: its potential is -F . r_P with r_P = S(x) q
// (the Hermite shapes above), and its gradient by central differences in every coordinate is
// minus its generalized force, at a bent and stretched state of the cable.
TEST(FlexibleForces, ADeadLoadAtAMaterialPointHasThePotentialMinusFDotRp) {
    const Vec2 F(0.3, -2.0);
    const double x = 0.6;
    const Model unloaded = test::scene(kCable);
    const Model model = test::scene(kCable + "forces:\n  - {name: push, type: point_force, body: {body: rope, at: 0.6}, "
                                             "force: [0.3, -2]}\n");
    ModelSystem system(model), unloaded_system(unloaded);
    ASSERT_TRUE(system.conservative());
    State state = system.initial_state();
    std::mt19937 rng(8);
    std::uniform_real_distribution<double> spread(-0.05, 0.05);
    for (int i = 0; i < state.q.size(); ++i) state.q[i] += spread(rng);
    auto load_potential = [&](const State& s) { return system.potential_energy(s) - unloaded_system.potential_energy(s); };
    const int o = model.flexible_bodies.front().offset;
    const Eigen::VectorXd shapes_F = hermite_force(x, F);  // S(x)^T F
    EXPECT_NEAR(load_potential(state), -shapes_F.dot(state.q.segment(o, shapes_F.size())), 1e-13);
    Eigen::VectorXd Q, Q_unloaded;
    system.generalized_forces(state, Q);
    unloaded_system.generalized_forces(state, Q_unloaded);
    Q -= Q_unloaded;
    const double h = 1e-6;
    double worst = 0.0;
    for (int i = 0; i < system.nv(); ++i) {
        State plus = state, minus = state;
        Eigen::VectorXd dv = Eigen::VectorXd::Zero(system.nv());
        dv[i] = h;
        system.advance_positions(plus.q, dv);
        system.advance_positions(minus.q, -dv);
        worst = std::max(worst, std::abs((load_potential(plus) - load_potential(minus)) / (2 * h) + Q[i]));
    }
    std::printf("dead load at x = %g: largest |dV/dq + Q| %.3g N\n", x, worst);
    // the differences carry the round-off of the cable's strain energy (about 10 J here, 1e-15
    // of it over h = 1e-6 is 1e-8 N); a wrong point or sign errs by the load itself
    EXPECT_LT(worst, 1e-7 * F.norm());
}

// The cable and a free bob joined by a spring from the cable's tip, no gravity.
std::string spring_scene(double damping) {
    return kCable + "bodies:\n  - {name: bob, mass: 0.5, inertia: 1.0e-3, position: [1.4, 0.1], velocity: [0.5, 2.0]}\n"
                    "forces:\n  - {name: spring, type: spring_damper, bodies: [{body: rope, node: 4}, bob], "
                    "stiffness: 50, rest_length: 0.3, damping: " + test::g17(damping) + "}\n";
}

TEST(FlexibleForces, TheMappedStiffnessIsMinusTheSecondDerivativeOfThePotential) {
    const Model model = test::scene(spring_scene(0.0));
    ModelSystem system(model);
    State state = system.initial_state();
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> jitter(-0.02, 0.02);
    for (int i = 0; i < state.q.size(); ++i) state.q[i] += jitter(rng);  // a deformed, rotated configuration
    Eigen::SparseMatrix<double> dQ_dq, dQ_dv;
    system.force_jacobians(state, dQ_dq, dQ_dv);
    const Eigen::MatrixXd K = Eigen::MatrixXd(dQ_dq);
    // -d2V/dq2 by central differences of the potential energy (the spring's and the cable's)
    const int n = system.nv();
    const double h = 1e-4;
    Eigen::MatrixXd hessian(n, n);
    auto V = [&](int i, double di, int j, double dj) {
        State s = state;
        Eigen::VectorXd dv = Eigen::VectorXd::Zero(n);
        dv[i] += di;
        dv[j] += dj;
        system.advance_positions(s.q, dv);
        return system.potential_energy(s);
    };
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            hessian(i, j) = (V(i, h, j, h) - V(i, h, j, -h) - V(i, -h, j, h) + V(i, -h, j, -h)) / (4 * h * h);
    // the bob's angle: the spring acts at its mass centre, so its column and row are zero
    const double error = (K + hessian).cwiseAbs().maxCoeff(), scale = K.cwiseAbs().maxCoeff();
    std::printf("mapped stiffness against -d2V/dq2: %.3g of %.3g\n", error, scale);
    EXPECT_LT(error, 1e-6 * scale);
    // the spring couples the tip node's position with the bob's (0, 1)
    EXPECT_GT(std::abs(K(0, model.flexible_bodies.front().offset + 16)), 1.0);
}

TEST(FlexibleForces, TheDampersVelocityJacobianIsMinusCNNTransposeAtTheTipNode) {
    const double c = 2.0;
    const Model model = test::scene(spring_scene(c));
    ModelSystem system(model);
    State state = system.initial_state();
    const int tip = model.flexible_bodies.front().offset + 16;  // the tip node's position
    state.q[tip + 1] += 0.05;  // the tip node up, its slope as it was
    Eigen::SparseMatrix<double> dQ_dq, dQ_dv;
    system.force_jacobians(state, dQ_dq, dQ_dv);
    const Eigen::MatrixXd D = Eigen::MatrixXd(dQ_dv);
    // the damper's force c (n . (v_bob - v_tip)) n on the tip, with n from the tip to the bob
    const Vec2 n = (state.q.head<2>() - state.q.segment<2>(tip)).normalized();
    const Eigen::Matrix2d cnn = c * n * n.transpose();
    Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(system.nv(), system.nv());
    expected.block<2, 2>(tip, tip) = -cnn;  // d Q_tip / d v_tip
    expected.block<2, 2>(tip, 0) = cnn;     // d Q_tip / d v_bob
    expected.block<2, 2>(0, 0) = -cnn;
    expected.block<2, 2>(0, tip) = cnn;
    EXPECT_LT((D - expected).cwiseAbs().maxCoeff(), 1e-7) << D.block(0, 0, 3, 3) << "\n" << D.block(tip, tip, 2, 2);
}

TEST(FlexibleForces, ASpringBetweenTheCableAndAFreeBodyConservesMomentumAndEnergy) {
    const Model model = test::scene(spring_scene(0.0));
    const FlexibleBodyInstance& rope = model.flexible_bodies.front();
    // linear momentum: the bob's m v plus the cable's integral of rho rdot, which is its
    // generalized force of a unit acceleration field dotted with its rates (sdk gravity_forces)
    auto momentum = [&](const State& s) {
        Vec2 p = 0.5 * s.v.head<2>();
        Eigen::VectorXd field(rope.size);
        for (int axis = 0; axis < 2; ++axis) {
            rope.body->gravity_forces(s.q.segment(rope.offset, rope.size), axis == 0 ? Vec3::UnitX() : Vec3::UnitY(),
                                      field);
            p[axis] += field.dot(s.v.segment(rope.v_offset, rope.size));
        }
        return p;
    };
    // 1 s, or 0.2 s in the sanitizer build: the largest potential (0.517 J) comes within the first
    // 0.2 s, so both builds check the same maximum (docs/ci.md)
    const double t_end = test::kSanitizerBuild ? 0.2 : 1.0;
    SimulationSettings settings = test::adaptive_run("augmented", "dopri5", 1e-10, t_end, t_end / 50);
    settings.diagnostics = true;
    std::vector<Vec2> momenta;
    std::vector<std::vector<double>> rows;
    const SimulationResult result = simulate(model, test::shared_registry(), settings, [&](const SimulationSample& s) {
        momenta.push_back(momentum(s.state));
        rows.push_back(*s.row);
        return true;
    });
    ASSERT_EQ(momenta.size(), 51u);
    double drift = 0.0;
    for (const Vec2& p : momenta) drift = std::max(drift, (p - momenta.front()).norm());
    EXPECT_NEAR(momenta.front().x(), 0.25, 1e-15);
    EXPECT_NEAR(momenta.front().y(), 1.0, 1e-15);
    // an explicit Runge-Kutta method keeps every linear invariant exactly: round-off only
    EXPECT_LT(drift, 1e-11);

    const auto column = [&](const std::string& name) {
        return static_cast<int>(std::find(result.columns.begin(), result.columns.end(), name) - result.columns.begin());
    };
    const int kinetic = column("kinetic_energy"), potential = column("potential_energy");
    ASSERT_LT(potential, static_cast<int>(result.columns.size()));
    const double E0 = rows.front()[kinetic] + rows.front()[potential];
    double energy_drift = 0.0, largest_potential = 0.0;
    for (const auto& row : rows) {
        energy_drift = std::max(energy_drift, std::abs(row[kinetic] + row[potential] - E0));
        largest_potential = std::max(largest_potential, row[potential]);
    }
    // the bob's 1/2 m v^2 = 1.0625 J; the spring starts stretched by 0.112 m (0.31 J), the cable
    // unstrained
    EXPECT_NEAR(rows.front()[kinetic], 0.5 * 0.5 * (0.25 + 4.0), 1e-12);
    EXPECT_NEAR(rows.front()[potential], 0.5 * 50 * std::pow(std::hypot(0.4, 0.1) - 0.3, 2), 1e-12);
    std::printf("cable + spring + bob over %g s: momentum drift %.3g, energy drift %.3g J of %.3g, largest potential "
                "%.3g J\n", t_end, drift, energy_drift, E0, largest_potential);
    // dopri5's local error under 1e-10 each step, a factor 10 for its accumulation
    EXPECT_LT(energy_drift, 10 * 1e-10 * E0);
    EXPECT_GT(largest_potential, 0.5);  // the bob's motion loads the spring and the cable: they do work
}

TEST(FlexibleForces, ACantileverUnderASmallTipLoadDeflectsByPL3Over3EI) {
    const double P = 1e-4 * kEI / (kLength * kLength);  // P L^2 / EI = 1e-4: the linear theory holds
    const Model model = test::scene(kCable + "joints:\n  - {name: clamp, type: fixed, bodies: [ground, {body: rope, node: 0}]}\n"
                                             "forces:\n  - {name: load, type: point_force, body: {body: rope, node: 4}, "
                                             "force: [0, " + test::g17(-P) + "]}\n");
    ModelSystem system(model);
    double residual = 0.0;
    const State rest = test::newton_equilibrium(system, system.initial_state(), residual);
    const int tip = model.flexible_bodies.front().offset + 16;
    const double deflection = -rest.q[tip + 1], expected = P * std::pow(kLength, 3) / (3 * kEI);
    std::printf("cantilever: tip deflection %.10g, P L^3 / (3 EI) = %.10g, residual %.3g\n", deflection, expected,
                residual);
    EXPECT_LT(residual, 1e-10);
    // Hermite cubics hold the cubic deflection of a tip load exactly; what is left is the
    // geometric nonlinearity, of relative order (P L^2 / EI)^2 = 1e-8
    EXPECT_NEAR(deflection, expected, 1e-6 * expected);
    EXPECT_NEAR(rest.q[tip], kLength, 1e-6);
}

// The message of the InputError the scene raises.
std::string refusal(const std::string& text) {
    return test::input_error_of([&] { test::scene(text, "cable.yaml"); });
}

TEST(FlexibleForces, BadPointsAreRefusedNamingTheForceAndTheBody) {
    const std::string whole = refusal(kCable + "forces:\n  - {name: push, type: point_force, body: rope, force: [0, 1]}\n");
    EXPECT_NE(whole.find("cable.yaml:5"), std::string::npos) << whole;
    EXPECT_NE(whole.find("force 'push'"), std::string::npos) << whole;
    EXPECT_NE(whole.find("node: K"), std::string::npos) << whole;
    const std::string outside =
        refusal(kCable + "forces:\n  - {name: push, type: point_force, body: {body: rope, at: 2}, force: [0, 1]}\n");
    EXPECT_NE(outside.find("'rope'"), std::string::npos) << outside;
    EXPECT_NE(outside.find("outside the beam"), std::string::npos) << outside;
    const std::string node =
        refusal(kCable + "forces:\n  - {name: push, type: point_force, body: {body: rope, node: 9}, force: [0, 1]}\n");
    EXPECT_NE(node.find("nodes 0 to 4"), std::string::npos) << node;
}

}  // namespace
}  // namespace mbd
