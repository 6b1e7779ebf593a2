// The motion of the beam_slider joint (core evaluation/beam_slider.hpp, docs/scene-format.md), a
// collar sliding without friction along an ANCF body, against
//   - the closed form s(t) = s0 + g sin(alpha) t^2 / 2 of a collar on a stiff inclined beam
//     clamped at both ends;
//   - conservation of energy under gravity (planar and spatial), and of linear and angular
//     momentum of a free beam and its collar (integrated over the beam's mass in the test);
//   - the same mechanism with a rigid bar and a prismatic joint (free collar, sleeve);
//   - statics: a bead at rest on a hanging cable, its reactions.
// Its rows against differences and its refusals: tests/test_beam_slider.cpp.
#include "support/beam_slider_scenes.hpp"
#include "support/sampled_run.hpp"
#include "support/test_support.hpp"

#include <mbd/model_system.hpp>
#include <mbd/reactions.hpp>
#include <mbd/statics_analysis.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace mbd {
namespace {

using test::cable;
constexpr double kG = test::kSliderG;
constexpr double kPi = test::kSliderPi;

using Trace = test::SampledRun;

Trace run(const Model& model, double t_end, double tolerance, int samples = 50) {
    return test::run_sampled(model, test::adaptive_run("augmented", "dopri5", tolerance, t_end, t_end / samples));
}

// A collar (0.5 kg, its point at its mass centre) on a straight cable inclined at alpha below the
// x axis, clamped at both ends, released at s0 = 0.25 m: if the cable were rigid it would slide
// as s(t) = s0 + g sin(alpha) t^2 / 2. The cable's bending under its weight and the collar's tilts
// its centre line by at most theta, which changes the tangential acceleration by at most
// g cos(alpha) theta: theta_w = 0.00802 w L^3 / EI (the largest slope of a clamped-clamped beam
// under a uniform load w = rho A g cos(alpha), from w x^2 (L - x)^2 / (24 EI)), theta_P =
// P L^2 / (16 EI) (the largest slope under a point load P = m g cos(alpha), a simply supported
// beam's, which bounds the clamped one's), doubled for a load applied suddenly (the cable starts
// straight): |s - s_closed| <= g cos(alpha) 2 (theta_w + theta_P) t^2 / 2.
TEST(BeamSlider, ACollarSlidesDownAStiffInclinedBeamAsGSinAlphaTSquaredOverTwo) {
    const double alpha = kPi / 6, L = 1.0, EI = 1.0e3, m = 0.5, s0 = 0.25;
    const Vec2 t_hat(std::cos(alpha), -std::sin(alpha));
    const Vec2 start = s0 * t_hat;
    const Model model = test::scene(
        "dimension: planar\ngravity: [0, -9.81]\nflexible_bodies:\n" +
        cable("rail", "[0, 0]", "[" + test::g17(L * t_hat.x()) + ", " + test::g17(L * t_hat.y()) + "]", 4, EI * 10,
              0.1) +
        "bodies:\n  - {name: collar, mass: 0.5, inertia: 1.0e-4, position: [" + test::g17(start.x()) + ", " +
        test::g17(start.y()) + "]}\n"
        "joints:\n  - {name: left, type: fixed, bodies: [ground, {body: rail, node: 0}]}\n"
        "  - {name: right, type: fixed, bodies: [ground, {body: rail, node: 4}]}\n"
        "  - {name: sleeve, type: beam_slider, bodies: [{body: rail, at: 0.25}, collar]}\n");
    const double t_end = 0.3;
    const Trace trace = run(model, t_end, 1e-8, 30);
    const double w = 1.0 * kG * std::cos(alpha), P = m * kG * std::cos(alpha);
    const double theta = 0.00802 * w * L * L * L / EI + P * L * L / (16 * EI);
    double worst = 0.0, across = 0.0;
    for (size_t r = 0; r < trace.rows.size(); ++r) {
        const double t = trace.at(r, "t");
        const Vec2 R(trace.at(r, "collar.x"), trace.at(r, "collar.y"));
        const double s = R.dot(t_hat), closed = s0 + 0.5 * kG * std::sin(alpha) * t * t;
        const double bound = kG * std::cos(alpha) * 2 * theta * t * t / 2;
        worst = std::max(worst, std::abs(s - closed) / std::max(bound, 1e-12));
        across = std::max(across, std::abs(R.x() * t_hat.y() - R.y() * t_hat.x()));
        if (r + 1 == trace.rows.size())
            std::printf("s(%g) = %.9f m against %.9f m (difference %.2e, bound %.2e); largest sag at the collar %.2e m\n", t,
                        s, closed, s - closed, bound, across);
    }
    EXPECT_LT(worst, 1.0);  // the difference within its bound at every sample
    EXPECT_LT(trace.largest("constraint_position_violation"), 1e-12);
}


// The example scene: a collar threaded on a flexible cantilever under gravity. Nothing dissipates,
// so kinetic energy (both bodies), strain energy and gravity's potential sum to a constant, to the
// integrator's tolerance on the energy the motion exchanges.
TEST(BeamSlider, ACollarOnAFlexibleCantileverKeepsTheEnergyAndStaysOnTheBeam) {
    const std::filesystem::path file = test::source_dir() / "examples/beam_slider/collar-on-cantilever.yaml";
    const Model model = test::scene(test::read_text(file), file.string());
    const double t_end = 0.5, tolerance = 1e-8;
    const Trace trace = run(model, t_end, tolerance, 30);
    const double scale = (0.5 + 1.0) * kG * 0.3;  // the bodies' weight times the collar's drop, about
    double slid = 0.0, tip = 0.0;
    for (size_t r = 0; r < trace.rows.size(); ++r) {
        slid = std::max(slid, trace.at(r, "collar.x") - 0.2);
        tip = std::min(tip, trace.at(r, "rail.node8.y"));
    }
    std::printf("collar on a cantilever over %g s: energy drift %.3g J of %.3g J, |C| %.3g, slid %.3f m, tip lowest %.3f m\n",
                t_end, trace.largest_energy_change(), scale, trace.largest("constraint_position_violation"), slid, tip);
    // the integrator's tolerance on the energy scale (measured 1000 times below; the factor 2 of
    // gamma's 2 Ndot^T w halved gives 1.1e-7 J)
    EXPECT_LT(trace.largest_energy_change(), tolerance * scale);
    EXPECT_LT(trace.largest("constraint_position_violation"), 1e-12);
    EXPECT_GT(slid, 0.1);  // the collar slid along the beam
    EXPECT_LT(tip, -0.1);  // and the beam bent under it
}


// The linear momentum and the angular momentum about the origin of a free cable (rho A = 1 kg/m)
// and its collar, the cable's by 4-point Gauss quadrature of rho A rdot and rho A r x rdot over
// each element (exact: r and rdot are cubic in x) from the cable's own material points.
struct Momenta {
    Vec2 linear = Vec2::Zero();
    double angular = 0.0;
};
Momenta momenta(const Model& model, const State& state, double collar_mass, double collar_inertia) {
    Momenta p;
    const Vec2 R = state.q.head<2>(), Rdot = state.v.head<2>();
    p.linear = collar_mass * Rdot;
    p.angular = collar_mass * (R.x() * Rdot.y() - R.y() * Rdot.x()) + collar_inertia * state.v[2];
    const FlexibleBodyInstance& f = model.flexible_bodies.front();
    const Eigen::VectorXd q = state.q.segment(f.offset, f.size), v = state.v.segment(f.v_offset, f.size);
    const int elements = f.body->node_count() - 1;
    const double l = f.body->node_parameters(1)[0];
    const double xi[4] = {0.0694318442029737, 0.3300094782075719, 0.6699905217924281, 0.9305681557970263};
    const double weight[4] = {0.1739274225587269, 0.3260725774412731, 0.3260725774412731, 0.1739274225587269};
    MaterialPoint point;
    for (int e = 0; e < elements; ++e)
        for (int g = 0; g < 4; ++g) {
            const double x = (e + xi[g]) * l;
            f.body->point(q, v, &x, point);
            const double dm = 1.0 * weight[g] * l;
            p.linear += dm * point.rdot.head<2>();
            p.angular += dm * (point.r.x() * point.rdot.y() - point.r.y() * point.rdot.x());
        }
    return p;
}

// No gravity, no other joint: a spinning collar whose point sits 0.1 m off its mass centre,
// threaded on a free cable at rest. The collar swings and bends the cable; the momenta of the two
// together stay what they were.
TEST(BeamSlider, AFreeCableAndItsSpinningCollarKeepTheirMomentaAndEnergy) {
    const double m = 0.5, J = 2.0e-3, omega = 10.0;
    // the collar's point (0.5, 0) on the cable, its centre at (0.5, 0.1), at rest: the point's
    // velocity omega k x (0, -0.1) = (1, 0) runs along the cable (a consistent start)
    const Model model = test::scene(
        "dimension: planar\nflexible_bodies:\n" + cable("rail", "[0, 0]", "[1, 0]", 4, 1.0e4, 1.0e-3) +
        "bodies:\n  - {name: collar, mass: 0.5, inertia: 2.0e-3, position: [0.5, 0.1], angular_velocity: 10}\n"
        "joints:\n  - {name: sleeve, type: beam_slider, bodies: [{body: rail, at: 0.5}, collar]}\n");
    SimulationSettings settings = test::adaptive_run("augmented", "dopri5", 1e-10, 0.3, 0.01);
    std::vector<State> states;
    simulate(model, test::shared_registry(), settings, [&](const SimulationSample& s) {
        states.push_back(s.state);
        return true;
    });
    ASSERT_GT(states.size(), 10u);
    ModelSystem system(model);
    const Momenta start = momenta(model, states.front(), m, J);
    const double E0 = system.kinetic_energy(states.front()) + system.potential_energy(states.front());
    double linear = 0.0, angular = 0.0, energy = 0.0, strain = 0.0;
    for (const State& s : states) {
        const Momenta p = momenta(model, s, m, J);
        linear = std::max(linear, (p.linear - start.linear).norm());
        angular = std::max(angular, std::abs(p.angular - start.angular));
        energy = std::max(energy, std::abs(system.kinetic_energy(s) + system.potential_energy(s) - E0));
        strain = std::max(strain, system.potential_energy(s));
    }
    std::printf("free cable and collar: p0 (%.6f, %.6f), L0 %.6f; largest change |p| %.2e, L %.2e, energy %.2e of "
                "%.4f J (largest strain energy %.3g J)\n",
                start.linear.x(), start.linear.y(), start.angular, linear, angular, energy, E0, strain);
    // the scales: the momenta the collar's point carries at the start
    EXPECT_LT(linear, 1e-9 * m * omega * 0.1);
    EXPECT_LT(angular, 1e-9 * (J * omega + m * 0.1 * omega * 0.1));
    EXPECT_LT(energy, 1e-8 * E0);
    EXPECT_GT(strain, 1e-2 * E0);  // the cable bent: the exchange the conservation is about
}


// The stiff cable pinned at one end and released horizontal with the collar on it, against the
// same mechanism with a rigid bar (1 kg, 1 m) pinned at one end and the collar on a prismatic
// joint. The prismatic joint also turns the collar with the bar: a free slider matches it when
// the collar's inertia is negligible (1e-6 kg m^2 against the bar's 1/3), a sleeve
// (`orientation: tangent`) with any inertia (its angle compared too). The cable bends by at most
// about a cantilever's static deflection under its weight and the collar's, w L^4 / (8 EI) +
// m g L^3 / (3 EI), doubled for the sudden release: the bound on the positions, and the
// cantilever's end slope w L^3 / (6 EI) + m g L^2 / (2 EI), doubled, on the angle.
void expect_agreement_with_a_rigid_bar(const std::string& collar_inertia, const std::string& orientation) {
    const double EI = 1.0e3, m = 0.5, L = 1.0;
    const std::string collar = "  - {name: collar, mass: 0.5, inertia: " + collar_inertia + ", position: [0.3, 0]}\n";
    const Model flexible = test::scene(
        "dimension: planar\ngravity: [0, -9.81]\nflexible_bodies:\n" +
        cable("rail", "[0, 0]", "[1, 0]", 4, EI * 10, 0.1) + "bodies:\n" + collar +
        "joints:\n  - {name: pivot, type: revolute, bodies: [ground, {body: rail, node: 0}]}\n"
        "  - {name: sleeve, type: beam_slider, bodies: [{body: rail, at: 0.3}, collar]" + orientation + "}\n");
    const Model rigid = test::scene(
        "dimension: planar\ngravity: [0, -9.81]\nbodies:\n"
        "  - {name: bar, mass: 1.0, inertia: 0.08333333333333333, position: [0.5, 0]}\n" +
        collar +
        "joints:\n  - {name: pivot, type: revolute, bodies: [ground, bar], point: [0, 0]}\n"
        "  - {name: sleeve, type: prismatic, bodies: [bar, collar], point: [0.3, 0], axis: [1, 0]}\n");
    const double t_end = 0.3;
    const Trace a = run(flexible, t_end, 1e-8, 15), b = run(rigid, t_end, 1e-10, 15);
    ASSERT_EQ(a.rows.size(), b.rows.size());
    const double bound = 2 * (kG * L * L * L * L / (8 * EI) + m * kG * L * L * L / (3 * EI));
    const double angle_bound = 2 * (kG * L * L * L / (6 * EI) + m * kG * L * L / (2 * EI));
    double worst = 0.0, angle = 0.0;
    for (size_t r = 0; r < a.rows.size(); ++r) {
        worst = std::max(worst, std::hypot(a.at(r, "collar.x") - b.at(r, "collar.x"),
                                           a.at(r, "collar.y") - b.at(r, "collar.y")));
        angle = std::max(angle, std::abs(a.at(r, "collar.angle") - b.at(r, "collar.angle")));
    }
    const size_t last = a.rows.size() - 1;
    std::printf("collar at t = %g: on the cable (%.6f, %.6f, %.6f rad), on the bar (%.6f, %.6f, %.6f rad); largest "
                "distance %.2e m (bound %.2e m), angle %.2e rad (bound %.2e)\n",
                t_end, a.at(last, "collar.x"), a.at(last, "collar.y"), a.at(last, "collar.angle"), b.at(last, "collar.x"),
                b.at(last, "collar.y"), b.at(last, "collar.angle"), worst, bound, angle, angle_bound);
    EXPECT_LT(worst, bound);
    EXPECT_LT(b.at(last, "collar.y"), -0.1);  // the mechanism moved well beyond the bound
    if (!orientation.empty()) EXPECT_LT(angle, angle_bound);
}

TEST(BeamSlider, AStiffCableAgreesWithARigidBarAndAPrismaticJoint) {
    expect_agreement_with_a_rigid_bar("1.0e-6", "");
}

TEST(BeamSlider, ASleeveOnAStiffCableAgreesWithARigidBarAndAPrismaticJoint) {
    expect_agreement_with_a_rigid_bar("2.0e-2", ", orientation: tangent");
}

// The spatial cable clamped at one end, gravity across it in two directions, a tumbling collar
// (its point off its mass centre) pushed along it: energy kept to the integrator's tolerance, the
// two rows satisfied, the cable bent out of both of its planes.
TEST(BeamSlider, ACollarOnASpatialCantileverKeepsTheEnergyAndStaysOnTheBeam) {
    const Model model = test::scene(
        "dimension: spatial\ngravity: [0, -4.0, -8.0]\nflexible_bodies:\n" +
        cable("rail", "[0, 0, 0]", "[1, 0, 0]", 4, 1.0e4, 1.0e-3) +
        "bodies:\n  - {name: collar, mass: 0.5, inertia: [1.0e-3, 2.0e-3, 2.5e-3], position: [0.3, 0, 0.05], "
        "velocity: [0.5, 0, 0], angular_velocity: [0, 0, 3]}\n"
        "joints:\n  - {name: clamp, type: fixed, bodies: [ground, {body: rail, node: 0}]}\n"
        "  - {name: sleeve, type: beam_slider, bodies: [{body: rail, at: 0.3}, collar]}\n");
    const double t_end = 0.4, tolerance = 1e-8;
    const Trace trace = run(model, t_end, tolerance, 20);
    const double scale = 1.5 * 9.0 * 0.3;  // the bodies' weight times a drop of the order of the tip's
    double y = 0.0, z = 0.0;
    for (size_t r = 0; r < trace.rows.size(); ++r) {
        y = std::min(y, trace.at(r, "rail.node4.y"));
        z = std::min(z, trace.at(r, "rail.node4.z"));
    }
    std::printf("spatial collar over %g s: energy drift %.3g J, |C| %.3g, tip lowest y %.3f m, z %.3f m, collar x %.3f m\n",
                t_end, trace.largest_energy_change(), trace.largest("constraint_position_violation"), y, z,
                trace.at(trace.rows.size() - 1, "collar.x"));
    EXPECT_LT(trace.largest_energy_change(), 10 * tolerance * scale);
    EXPECT_LT(trace.largest("constraint_position_violation"), 1e-12);
    EXPECT_LT(y, -0.02);
    EXPECT_LT(z, -0.05);
}

// ---------------------------------------------------------------- statics

// A bead (0.5 kg) threaded on a cable (1 kg/m, 1 m) pinned at both ends, under gravity, started
// at x = 0.3 on the straight cable: without friction it can rest only at the lowest point, by
// symmetry the middle. The pins carry half of the total weight each; the slider holds the bead
// up with its weight m g and presses the cable down with as much at the bead's point.
TEST(BeamSlider, MbdStaticsRestsABeadAtTheMiddleOfAHangingCable) {
    const double m = 0.5;
    const Model model = test::scene(
        "dimension: planar\ngravity: [0, -9.81]\nflexible_bodies:\n" + cable("rope", "[0, 0]", "[1, 0]", 8, 1.0e4, 1.0e-3) +
        "bodies:\n  - {name: bead, mass: 0.5, inertia: 1.0e-3, position: [0.3, 0]}\n"
        "joints:\n  - {name: left, type: revolute, bodies: [ground, {body: rope, node: 0}]}\n"
        "  - {name: right, type: revolute, bodies: [ground, {body: rope, node: 8}]}\n"
        "  - {name: sleeve, type: beam_slider, bodies: [{body: rope, at: 0.3}, bead]}\n");
    StaticsOptions options;
    options.analyse_stability = false;
    const StaticsReport report = run_statics(model, test::shared_registry(), options);
    ASSERT_TRUE(report.result.converged) << report.result.status << ": " << report.result.message;
    const State& x = report.result.state;
    const int o = model.flexible_bodies.front().offset;
    ModelSystem system(model);
    const std::vector<JointReaction> reactions = joint_reactions(system, x, report.result.lambda);
    const BodyReaction& on_rope = reactions[2].on[0];
    const BodyReaction& on_bead = reactions[2].on[1];
    std::printf("bead at (%.12f, %.9f), the cable's middle node at (%.12f, %.9f); pins' vertical reactions %.9f, "
                "%.9f N; on the bead (%.2e, %.9f) N, on the cable (%.2e, %.9f) N at (%.9f, %.9f)\n",
                x.q[0], x.q[1], x.q[o + 16], x.q[o + 17], report.reactions[0].force.y(), report.reactions[1].force.y(),
                on_bead.force.x(), on_bead.force.y(), on_rope.force.x(), on_rope.force.y(), on_rope.point.x(),
                on_rope.point.y());
    EXPECT_NEAR(x.q[0], 0.5, 1e-9);
    EXPECT_LT(x.q[1], -0.01);  // the cable sags under the bead
    EXPECT_NEAR(x.q[1], x.q[o + 17], 1e-9);  // on the cable: the middle node (node 4's y)
    const double half_weight = (1.0 + m) * kG / 2;
    EXPECT_NEAR(report.reactions[0].force.y(), half_weight, 1e-8 * half_weight);
    EXPECT_NEAR(report.reactions[1].force.y(), half_weight, 1e-8 * half_weight);
    EXPECT_TRUE(on_rope.material_frame);
    EXPECT_LT((on_bead.force - Vec3(0, m * kG, 0)).norm(), 1e-8 * m * kG);
    EXPECT_LT((on_rope.force - Vec3(0, -m * kG, 0)).norm(), 1e-8 * m * kG);
    EXPECT_LT((on_rope.point - Vec3(x.q[0], x.q[1], 0)).norm(), 1e-12);  // where the bead is
}

}  // namespace
}  // namespace mbd
