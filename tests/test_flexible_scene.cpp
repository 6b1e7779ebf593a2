// Flexible bodies inside the engine (`flexible_bodies:`, docs/scene-format.md): an ANCF cable
// declared in a scene, joints at its nodes, simulated through `simulate` with the augmented
// formulation. Oracles: free fall (every node at y0 - g t^2 / 2, exactly, since gravity alone
// deforms nothing), conservation of energy (no dissipation anywhere), the joints' constraint
// violation, the mesh's node positions at t = 0 from the scene's end points, and refusals of bad
// input naming the body and its file:line.
#include "support/input_files.hpp"
#include "support/sampled_run.hpp"
#include "support/sanitizer_build.hpp"
#include "support/test_support.hpp"

#include <mbd/model_system.hpp>
#include <mbd/output_sink.hpp>
#include <mbd/simulation.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

namespace mbd {
namespace {

constexpr double kG = 9.81;

// A planar cable from (0, 0) to (L, 0): rho A = 1 kg/m, EI = 10 N m^2, EA = 1e4 N (axial
// frequencies a few hundred rad/s: an explicit integrator resolves them in a fraction of a second).
std::string cable(const std::string& name, int elements, double length = 1.0) {
    return "  - {name: " + name + ", type: ancf_cable, from: [0, 0], to: [" + test::g17(length) +
           ", 0], elements: " + std::to_string(elements) +
           ", modulus: 1.0e4, area: 1.0, second_moment: 1.0e-3, density: 1.0}\n";
}

std::string scene_text(const std::string& flexible, const std::string& rest = "", bool gravity = true) {
    return "dimension: planar\n" + std::string(gravity ? "gravity: [0, -9.81]\n" : "") + "flexible_bodies:\n" +
           flexible + rest;
}

using Trace = test::SampledRun;

Trace run(const Model& model, double t_end, double tolerance, const std::string& formulation = "augmented") {
    return test::run_sampled(model, test::adaptive_run(formulation, "dopri5", tolerance, t_end, t_end / 50));
}

TEST(FlexibleScene, AFreeCableFallsAsAPointUnderGravityAndKeepsItsEnergy) {
    const Model model = test::scene(scene_text(cable("rope", 4)));
    const Trace trace = run(model, 0.5, 1e-10);
    ASSERT_EQ(trace.rows.size(), 51u);
    double worst = 0.0;
    for (const auto& row : trace.rows) {
        const double t = row[0];
        for (int k = 0; k <= 4; ++k) {
            const std::string node = "rope.node" + std::to_string(k);
            worst = std::max(worst, std::abs(row[trace.column(node + ".x")] - 0.25 * k));
            worst = std::max(worst, std::abs(row[trace.column(node + ".y")] + 0.5 * kG * t * t));
            worst = std::max(worst, std::abs(row[trace.column(node + ".vy")] + kG * t));
        }
    }
    std::printf("free fall: largest node error %.3g m, energy change %.3g J\n", worst, trace.largest_energy_change());
    // exact but for round-off: a constant acceleration is integrated exactly by any Runge-Kutta
    // method of order 2 or more, and a uniform field strains nothing
    EXPECT_LT(worst, 1e-10);
    // m g (g t^2 / 2) = 1 * 9.81 * 1.23 = 12 J changes from potential to kinetic
    EXPECT_NEAR(trace.rows.back()[trace.column("kinetic_energy")], 0.5 * std::pow(kG * 0.5, 2), 1e-8);
    EXPECT_LT(trace.largest_energy_change(), 1e-8);
}

// The flexible pendulum: the cable pinned at its node 0, released horizontal.
const std::string kPin = "joints:\n  - {name: pin, type: revolute, bodies: [ground, {body: rope, node: 0}]}\n";

// Over 10 s (1 s in the sanitizer build, which reaches every path of the cable's evaluation in
// its first steps: the tip's first swing below the pin, with every bound as in Release).
TEST(FlexibleScene, TheFlexiblePendulumConservesEnergyAndKeepsItsPin) {
    const Model model = test::scene(scene_text(cable("rope", 4), kPin));
    const double t_end = test::kSanitizerBuild ? 1.0 : 10.0;
    const Trace trace = run(model, t_end, 1e-9);
    ASSERT_EQ(trace.rows.size(), 51u);
    const double scale = 1.0 * kG * 0.5;  // m g L / 2, the energy the swing exchanges
    const double drift = trace.largest_energy_change();
    const double violation = trace.largest("constraint_position_violation");
    double pin = 0.0;
    for (const auto& row : trace.rows)
        pin = std::max({pin, std::abs(row[trace.column("rope.node0.x")]), std::abs(row[trace.column("rope.node0.y")])});
    // the cable swings down: its tip passes well below the pin
    double lowest = 0.0;
    for (const auto& row : trace.rows) lowest = std::min(lowest, row[trace.column("rope.node4.y")]);
    std::printf("flexible pendulum over %g s: energy drift %.3g J of %.3g, |C| %.3g, pin %.3g m, tip lowest %.3g m\n",
                t_end, drift, scale, violation, pin, lowest);
    // dopri5 keeps each step's local error under its tolerance (relative and absolute, 1e-9), so
    // the energy it exchanges stays conserved to that tolerance on the energy scale; a factor 10
    // of room for its accumulation over 10 s. Every output state is projected onto C = 0 to the
    // projection tolerance (1e-12, FormulationOptions).
    EXPECT_LT(drift, 10 * 1e-9 * scale);
    EXPECT_LT(violation, 1e-12);
    EXPECT_LT(pin, 1e-12);
    EXPECT_LT(lowest, -0.8);
}

TEST(FlexibleScene, ARigidBobPinnedToTheCablesFreeEndKeepsEnergyAndItsJoint) {
    const std::string rest =
        "bodies:\n  - {name: bob, mass: 0.5, inertia: 1.0e-3, position: [1, 0]}\n"
        "joints:\n  - {name: pin, type: revolute, bodies: [ground, {body: rope, node: 0}]}\n"
        "  - {name: tip, type: revolute, bodies: [{body: rope, at: 1.0}, bob]}\n";
    const Model model = test::scene(scene_text(cable("rope", 4), rest));
    const Trace trace = run(model, test::kSanitizerBuild ? 1.0 : 3.0, 1e-9);  // as the pendulum above
    const double scale = 1.5 * kG * 1.0;
    double joint = 0.0;  // the bob's centre on the cable's tip
    for (const auto& row : trace.rows)
        joint = std::max(joint, std::hypot(row[trace.column("bob.x")] - row[trace.column("rope.node4.x")],
                                           row[trace.column("bob.y")] - row[trace.column("rope.node4.y")]));
    double lowest = 0.0;
    for (const auto& row : trace.rows) lowest = std::min(lowest, row[trace.column("bob.y")]);
    std::printf("cable with bob: energy drift %.3g J, |C| %.3g, tip-bob gap %.3g m, bob lowest %.3g m\n",
                trace.largest_energy_change(), trace.largest("constraint_position_violation"), joint, lowest);
    // the bounds of the pendulum above: the integrator's tolerance on the energy scale, the
    // projection's on the joints
    EXPECT_LT(trace.largest_energy_change(), 10 * 1e-9 * scale);
    EXPECT_LT(trace.largest("constraint_position_violation"), 1e-12);
    EXPECT_LT(joint, 1e-12);
    EXPECT_LT(lowest, -0.8);
}

// The reaction on the cable at a joint whose second body is the cable's material frame
// (`mbd simulate --reactions`), against the bob's own law of motion: the hinge pushes the bob
// with minus that reaction, so m a_bob = m g - F_tip (its acceleration by central differences of
// its velocity, output every 0.5 ms; the hinge at the bob's centre gives no moment). The pin's
// reaction column is there too.
TEST(FlexibleScene, TheReactionOnTheCableAtAHingeIsWhatMovesTheBob) {
    const double m = 0.5, h = 5e-4;
    const std::string rest =
        "bodies:\n  - {name: bob, mass: 0.5, inertia: 1.0e-3, position: [1, 0]}\n"
        "joints:\n  - {name: pin, type: revolute, bodies: [ground, {body: rope, node: 0}]}\n"
        "  - {name: tip, type: revolute, bodies: [bob, {body: rope, at: 1.0}]}\n";
    const Model model = test::scene(scene_text(cable("rope", 4), rest));
    SimulationSettings settings = test::adaptive_run("augmented", "dopri5", 1e-10, 0.2, h);
    settings.reactions = true;
    const Trace trace = test::run_sampled(model, settings);
    ASSERT_GE(trace.column("pin.fx"), 0);
    double worst = 0.0, largest = 0.0;
    for (size_t k = 1; k + 1 < trace.rows.size(); ++k) {
        const double ax = (trace.at(k + 1, "bob.vx") - trace.at(k - 1, "bob.vx")) / (2 * h);
        const double ay = (trace.at(k + 1, "bob.vy") - trace.at(k - 1, "bob.vy")) / (2 * h);
        const double fx = trace.at(k, "tip.fx"), fy = trace.at(k, "tip.fy");
        worst = std::max(worst, std::hypot(m * ax + fx, m * ay + m * kG + fy));
        largest = std::max(largest, std::hypot(fx, fy));
        EXPECT_NEAR(trace.at(k, "tip.tz"), 0.0, 1e-9);
    }
    std::printf("hinge on the cable: largest |m a - m g + F_tip| %.3g N of |F_tip| up to %.3g N\n", worst, largest);
    EXPECT_GT(largest, 0.5 * m * kG);  // the hinge carries a good part of the bob's weight
    EXPECT_LT(worst, 1e-2 * largest);   // the differences' error (axial vibration at ~150 rad/s)
}

TEST(FlexibleScene, TheCsvHasEachNodesPositionAndVelocityUnderItsBodysName) {
    const Model model = test::scene(scene_text(cable("rope", 3, 0.9), kPin));
    const auto csv = test::scratch("flexible_csv") / "cable.csv";
    const std::unique_ptr<OutputSink> sink = csv_output_format().make(csv);  // the sink of `--output x.csv`
    simulate(model, test::shared_registry(), test::adaptive_run("augmented", "dopri5", 1e-9, 0.1, 0.01), {},
             {sink.get()});
    const test::Csv table = test::read_csv(csv);
    const std::vector<std::string> expected{"t",           "rope.node0.x", "rope.node0.y", "rope.node0.vx",
                                            "rope.node0.vy", "rope.node1.x"};
    for (size_t k = 0; k < expected.size(); ++k) EXPECT_EQ(table.header[k], expected[k]);
    EXPECT_EQ(table.header.back(), "rope.node3.vy");
    EXPECT_EQ(table.header.size(), 1u + 4 * 4);
    // the mesh at t = 0: nodes 0.3 m apart along x from the pin
    for (int k = 0; k <= 3; ++k) {
        EXPECT_NEAR(table.rows[0][table.column("rope.node" + std::to_string(k) + ".x")], 0.3 * k, 1e-15);
        EXPECT_NEAR(table.rows[0][table.column("rope.node" + std::to_string(k) + ".y")], 0.0, 1e-15);
    }
    // and later the free end has fallen while the pinned node stays
    EXPECT_LT(table.rows.back()[table.column("rope.node3.y")], -0.01);
    EXPECT_NEAR(table.rows.back()[table.column("rope.node0.y")], 0.0, 1e-9);
}

// The message of the InputError the scene raises.
std::string refusal(const std::string& text) {
    return test::input_error_of([&] { test::scene(text, "cable.yaml"); });
}

TEST(FlexibleScene, BadInputNamesTheBodyAndTheLine) {
    const std::string head = scene_text(cable("rope", 4));
    auto joint = [&](const std::string& point) {
        return head + "joints:\n  - {name: pin, type: revolute, bodies: [ground, " + point + "]}\n";
    };
    const std::string unknown_node = refusal(joint("{body: rope, node: 5}"));
    EXPECT_NE(unknown_node.find("cable.yaml:6"), std::string::npos) << unknown_node;
    EXPECT_NE(unknown_node.find("'rope'"), std::string::npos) << unknown_node;
    EXPECT_NE(unknown_node.find("nodes 0 to 4"), std::string::npos) << unknown_node;

    const std::string outside = refusal(joint("{body: rope, at: 1.5}"));
    EXPECT_NE(outside.find("cable.yaml:6"), std::string::npos) << outside;
    EXPECT_NE(outside.find("'rope'"), std::string::npos) << outside;
    EXPECT_NE(outside.find("outside the beam"), std::string::npos) << outside;

    const std::string no_point = refusal(joint("rope"));
    EXPECT_NE(no_point.find("node: K"), std::string::npos) << no_point;

    const std::string undefined = refusal(joint("{body: rop, node: 0}"));
    EXPECT_NE(undefined.find("undefined flexible body 'rop'"), std::string::npos) << undefined;
    EXPECT_NE(undefined.find("'rope'"), std::string::npos) << undefined;

    const std::string both = refusal(joint("{body: rope, node: 0, at: 0.5}"));
    EXPECT_NE(both.find("one of them"), std::string::npos) << both;

    const std::string bad_modulus = refusal(scene_text(test::replaced(cable("rope", 4), "modulus: 1.0e4", "modulus: 0")));
    EXPECT_NE(bad_modulus.find("body 'rope'"), std::string::npos) << bad_modulus;
    EXPECT_NE(bad_modulus.find("cable.yaml:4"), std::string::npos) << bad_modulus;

    const std::string clash = refusal(scene_text(cable("rope", 2)) +
                                      "bodies:\n  - {name: rope, mass: 1, inertia: 1}\n");
    EXPECT_NE(clash.find("rope"), std::string::npos) << clash;
}

TEST(FlexibleScene, FormulationsThatDoNotTakeFlexibleBodiesRefuseNamingTheBody) {
    const Model model = test::scene(scene_text(cable("rope", 2), kPin), "cable.yaml");
    for (const std::string formulation : {"embedding", "amalgamated", "hamiltonian"}) {
        SimulationSettings settings = test::adaptive_run(formulation, "dopri5", 1e-8, 0.1, 0.05);
        try {
            check_simulation_method(model, test::shared_registry(), settings);
            ADD_FAILURE() << formulation << " took the flexible body";
        } catch (const InputError& e) {
            const std::string message = e.what();
            EXPECT_NE(message.find("flexible body 'rope'"), std::string::npos) << message;
            EXPECT_NE(message.find("cable.yaml:4"), std::string::npos) << message;
            EXPECT_NE(message.find("augmented"), std::string::npos) << message;
        }
    }
    // the automatic choice takes augmented
    SimulationSettings automatic = test::adaptive_run("", "dopri5", 1e-8, 0.1, 0.05);
    EXPECT_NO_THROW(check_simulation_method(model, test::shared_registry(), automatic));
}

}  // namespace
}  // namespace mbd
