// The beam_slider joint (core evaluation/beam_slider.hpp, docs/scene-format.md): a collar's point
// sliding without friction along the centre line of an ANCF body. Oracles:
//   - central differences of the rows C (s* re-solved at each probe) for the Jacobian, and of C
//     along a smooth motion for gamma (Cddot = J vdot - gamma), at a deformed, moving state
//     whose collar point is on the curve and leaves it at a non-zero rate (planar and spatial);
//   - the closed form s(t) = s0 + g sin(alpha) t^2 / 2 of a collar on a stiff inclined beam
//     clamped at both ends;
//   - conservation of energy under gravity, and of linear and angular momentum of a free beam and
//     its collar (integrated over the beam's mass in the test);
//   - the same mechanism with a rigid bar and a prismatic joint;
//   - refusals of bad input naming the joint and file:line, and a collar that runs off the beam.
#include "support/input_files.hpp"
#include "support/sampled_run.hpp"
#include "support/test_support.hpp"

#include <mbd/model_system.hpp>
#include <mbd/reactions.hpp>
#include <mbd/statics_analysis.hpp>
#include <mbd/sdk/rotation.hpp>
#include <mbd/sdk/text.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>

namespace mbd {
namespace {

constexpr double kG = 9.81;
constexpr double kPi = 3.14159265358979323846;

// A cable `name` between two points (rho A = density, area 1).
std::string cable(const std::string& name, const std::string& from, const std::string& to, int elements,
                  double modulus, double second_moment, const std::string& extra = "") {
    return "  - {name: " + name + ", type: ancf_cable, from: " + from + ", to: " + to +
           ", elements: " + std::to_string(elements) + ", modulus: " + test::g17(modulus) +
           ", area: 1.0, second_moment: " + test::g17(second_moment) + ", density: 1.0" + extra + "}\n";
}

// ---------------------------------------------------------------- rows against finite differences

// A smooth motion of a slider scene (a cable `rail`, a rigid `collar`, the joint `sleeve`): the
// cable's coordinates q_b(t) = q_0 + t v_0 + t^2 a_0 / 2, and the collar's point at the cable's
// material point s(t) moved off the centre line by offsets(t) along the material frame's
// normal(s) (the frame's y axis; spatial: its y and z axes), the collar turning at a prescribed
// rate. Positions from the motion; the collar's translational velocity and acceleration by
// fourth-order differences in t.
class SliderMotion {
public:
    SliderMotion(const Model& model, Eigen::VectorXd q0, Eigen::VectorXd v0, Eigen::VectorXd a0)
        : model_(model), q0_(std::move(q0)), v0_(std::move(v0)), a0_(std::move(a0)) {
        const JointInstance& joint = model.joints.front();
        u_bar_ = joint.markers[1].u_bar;
        planar_ = model.dimension == Dimension::Planar;
    }

    State state(double t) const {
        State s;
        s.t = 0.0;
        s.q = positions(t);
        s.v = velocities(t);
        return s;
    }
    Eigen::VectorXd accelerations(double t) const {
        Eigen::VectorXd a = Eigen::VectorXd::Zero(model_.nv());
        const Vec3 R2 = differenced(t, 2);
        if (planar_) {
            a.head<2>() = R2.head<2>();
            a[2] = kTurn[2];
        } else {
            a.head<3>() = R2;
            a.segment<3>(3) = kAxis * kTurn[2];
        }
        a.tail(model_.flexible_coordinates()) = a0_;
        return a;
    }

private:
    static constexpr double kSlide[3] = {0.37, 0.8, -0.6};   // s(t) = s0 + s1 t + s2 t^2 / 2
    static constexpr double kOff[2][3] = {{0.0, 0.2, 0.5}, {0.0, -0.3, 0.4}};  // offsets(t), likewise
    static constexpr double kTurn[3] = {0.3, 1.1, -0.7};     // the collar's turn angle, likewise
    inline static const Vec3 kAxis = Vec3(0.36, 0.48, 0.8);  // the spatial collar's turning axis (unit)

    static double quadratic(const double (&c)[3], double t) { return c[0] + c[1] * t + 0.5 * c[2] * t * t; }
    Eigen::VectorXd beam(double t) const { return q0_ + t * v0_ + 0.5 * t * t * a0_; }

    // the collar's mass centre at t: its point P on the offset material point, minus A u_bar
    Vec3 centre(double t) const {
        const FlexibleBody& body = *model_.flexible_bodies.front().body;
        const Eigen::VectorXd q = beam(t), v = Eigen::VectorXd::Zero(q.size());
        const double s = quadratic(kSlide, t);
        MaterialFrame frame;
        body.frame(q, v, &s, frame);
        if (planar_) {
            const Vec2 normal(-std::sin(frame.planar.theta), std::cos(frame.planar.theta));
            const Vec2 P = frame.planar.R + quadratic(kOff[0], t) * normal;
            const Vec2 R = P - planar_rotation(quadratic(kTurn, t)) * u_bar_.head<2>();
            return Vec3(R.x(), R.y(), 0.0);
        }
        const Vec3 P = frame.spatial.R + quadratic(kOff[0], t) * frame.spatial.A.col(1) +
                       quadratic(kOff[1], t) * frame.spatial.A.col(2);
        return P - orientation(t) * u_bar_;
    }
    Mat3 orientation(double t) const {
        return rotation_from_euler_parameters(euler_parameters_from_axis_angle(kAxis, quadratic(kTurn, t)));
    }
    // d^k/dt^k of the collar's centre, k = 1 or 2, by fourth-order central differences
    Vec3 differenced(double t, int k) const {
        const double h = 1e-3;
        const Vec3 m2 = centre(t - 2 * h), m1 = centre(t - h), p1 = centre(t + h), p2 = centre(t + 2 * h);
        if (k == 1) return (m2 - 8.0 * m1 + 8.0 * p1 - p2) / (12.0 * h);
        return (-m2 + 16.0 * m1 - 30.0 * centre(t) + 16.0 * p1 - p2) / (12.0 * h * h);
    }

    Eigen::VectorXd positions(double t) const {
        Eigen::VectorXd q(model_.nq());
        const Vec3 R = centre(t);
        if (planar_) {
            q.head<2>() = R.head<2>();
            q[2] = quadratic(kTurn, t);
        } else {
            q.head<3>() = R;
            q.segment<4>(3) = euler_parameters_from_axis_angle(kAxis, quadratic(kTurn, t));
        }
        q.tail(model_.flexible_coordinates()) = beam(t);
        return q;
    }
    Eigen::VectorXd velocities(double t) const {
        Eigen::VectorXd v(model_.nv());
        const Vec3 R1 = differenced(t, 1);
        const double turn_rate = kTurn[1] + kTurn[2] * t;
        if (planar_) {
            v.head<2>() = R1.head<2>();
            v[2] = turn_rate;
        } else {
            v.head<3>() = R1;
            v.segment<3>(3) = kAxis * turn_rate;  // about a fixed axis: the same in body axes
        }
        v.tail(model_.flexible_coordinates()) = v0_ + t * a0_;
        return v;
    }

    const Model& model_;
    Eigen::VectorXd q0_, v0_, a0_;
    Vec3 u_bar_ = Vec3::Zero();
    bool planar_ = true;
};

// The scene's cable bent out of its straight line, moving and accelerating: smooth made-up
// fields on every coordinate.
struct CableMotion {
    Eigen::VectorXd q0, v0, a0;
};
// per_node: the coordinates of a node (the cables' [r, r'], the ancf_beam's [r, r_x, r_y]).
CableMotion bent_cable(const Model& model, int dimension, int per_node) {
    const FlexibleBodyInstance& f = model.flexible_bodies.front();
    CableMotion m{f.body->initial_coordinates(), Eigen::VectorXd(f.size), Eigen::VectorXd(f.size)};
    for (int i = 0; i < f.size; ++i) {
        const int node = i / per_node, component = i % per_node;
        const double x = m.q0[node * per_node];  // the node's reference x (the cable starts on the x axis)
        if (component == 1) m.q0[i] += 0.1 * std::sin(kPi * x);                 // y
        if (component == dimension + 1) m.q0[i] += 0.1 * kPi * std::cos(kPi * x);  // y'
        if (dimension == 3 && component == 2) m.q0[i] += 0.05 * std::sin(2 * kPi * x);
        if (dimension == 3 && component == 5) m.q0[i] += 0.1 * kPi * std::cos(2 * kPi * x);
        m.q0[i] += 0.01 * std::sin(1.7 * i + 0.2);
        m.v0[i] = 0.4 * std::cos(0.9 * i + 0.5);
        m.a0[i] = 0.6 * std::sin(1.1 * i + 1.3);
    }
    return m;
}

std::string format_vector(const Eigen::VectorXd& v) {
    std::string text = "[";
    for (int i = 0; i < v.size(); ++i) text += (i ? ", " : "") + format_number(v[i]);
    return text + "]";
}

// C of the scene's rows at a state.
Eigen::VectorXd rows_at(ModelSystem& system, const State& state) {
    ConstraintValues cv;
    system.constraints(state, cv, false);
    return cv.C;
}

// Checks J against central differences of C over every velocity direction, and gamma against
// J vdot - Cddot with Cddot by fourth-order differences of C along the motion.
void expect_rows_match_differences(const Model& model, const SliderMotion& motion) {
    ModelSystem system(model);
    const State x = motion.state(0.0);
    ConstraintValues cv;
    system.constraints(x, cv, false);
    const Eigen::MatrixXd J = cv.J;
    const int rows = static_cast<int>(cv.C.size());

    const double h = 1e-6;
    double worst_J = 0.0;
    for (int k = 0; k < model.nv(); ++k) {
        State plus = x, minus = x;
        Eigen::VectorXd dv = Eigen::VectorXd::Zero(model.nv());
        dv[k] = h;
        advance_positions(model, plus.q, dv);
        advance_positions(model, minus.q, -dv);
        const Eigen::VectorXd fd = (rows_at(system, plus) - rows_at(system, minus)) / (2 * h);
        worst_J = std::max(worst_J, (fd - J.col(k)).cwiseAbs().maxCoeff());
    }
    const double J_scale = J.cwiseAbs().maxCoeff();

    const double dt = 1e-3;
    Eigen::VectorXd C[5];
    for (int i = 0; i < 5; ++i) C[i] = rows_at(system, motion.state((i - 2) * dt));
    const Eigen::VectorXd Cddot = (-C[0] + 16.0 * C[1] - 30.0 * C[2] + 16.0 * C[3] - C[4]) / (12.0 * dt * dt);
    const Eigen::VectorXd J_vdot = J * motion.accelerations(0.0);
    const Eigen::VectorXd expected = J_vdot - Cddot;
    const double gamma_error = (cv.gamma - expected).cwiseAbs().maxCoeff();
    const double gamma_scale = std::max(J_vdot.cwiseAbs().maxCoeff(), Cddot.cwiseAbs().maxCoeff());
    const Eigen::VectorXd Cdot = J * x.v;
    std::printf("%s: |C| %.2e, |Cdot| %.3g, J error %.2e of %.3g, gamma %s against %s (error %.2e of %.3g)\n",
                to_string(model.dimension), cv.C.cwiseAbs().maxCoeff(), Cdot.cwiseAbs().maxCoeff(), worst_J, J_scale,
                format_vector(cv.gamma).c_str(), format_vector(expected).c_str(), gamma_error, gamma_scale);
    EXPECT_EQ(rows, model.joints.front().joint->rows());
    for (int r = 0; r < rows; ++r)  // the point is on the curve at t = 0 (a sleeve's angle row may be off)
        if (model.joints.front().joint->row_name(r).rfind("normal", 0) == 0) EXPECT_LT(std::abs(cv.C[r]), 1e-12);
    EXPECT_GT(Cdot.cwiseAbs().maxCoeff(), 0.1);     // and leaving it: every term of gamma is alive
    EXPECT_LT(worst_J, 1e-7 * J_scale);
    EXPECT_LT(gamma_error, 1e-6 * gamma_scale);
}

const std::string kCollarPlanar =
    "bodies:\n  - {name: collar, mass: 0.2, inertia: 1.0e-3, position: [0.35, 0.08], angle: 0.2}\n"
    "joints:\n  - {name: sleeve, type: beam_slider, bodies: [{body: rail, at: 0.37}, collar]}\n";

TEST(BeamSlider, PlanarRowsMatchFiniteDifferencesAtADeformedMovingState) {
    const Model model = test::scene("dimension: planar\nflexible_bodies:\n" +
                                    cable("rail", "[0, 0]", "[1, 0]", 4, 1.0e4, 1.0e-3) + kCollarPlanar);
    const CableMotion m = bent_cable(model, 2, 4);
    expect_rows_match_differences(model, SliderMotion(model, m.q0, m.v0, m.a0));
}

// The sleeve: the collar also keeps its angle to the tangent (`orientation: tangent`), a second
// row C = theta - atan2(r_s) - offset whose Jacobian and gamma hold the tangent's turn with s*.
TEST(BeamSlider, ASleevesAngleRowMatchesFiniteDifferences) {
    const Model model = test::scene("dimension: planar\nflexible_bodies:\n" +
                                    cable("rail", "[0, 0]", "[1, 0]", 4, 1.0e4, 1.0e-3) +
                                    test::replaced(kCollarPlanar, "collar]}", "collar], orientation: tangent}"));
    ASSERT_EQ(model.joints.front().joint->rows(), 2);
    const CableMotion m = bent_cable(model, 2, 4);
    expect_rows_match_differences(model, SliderMotion(model, m.q0, m.v0, m.a0));
}

// The shear-deformable beam's centre line (its nodes' r and r_x of [r, r_x, r_y]); the collar's
// offset follows the cross-section's frame, which shears away from the centre line's normal.
TEST(BeamSlider, RowsOnTheShearDeformableBeamMatchFiniteDifferences) {
    const Model model = test::scene(
        "dimension: planar\nflexible_bodies:\n  - {name: rail, type: ancf_beam, from: [0, 0], to: [1, 0], elements: 4, "
        "modulus: 1.0e6, shear_modulus: 4.0e5, area: 1.0e-2, second_moment: 1.0e-5, density: 100.0}\n" +
        kCollarPlanar);
    const CableMotion m = bent_cable(model, 2, 6);
    expect_rows_match_differences(model, SliderMotion(model, m.q0, m.v0, m.a0));
}

TEST(BeamSlider, SpatialRowsMatchFiniteDifferencesAtADeformedMovingState) {
    const Model model = test::scene(
        "dimension: spatial\nflexible_bodies:\n" + cable("rail", "[0, 0, 0]", "[1, 0, 0]", 4, 1.0e4, 1.0e-3) +
        "bodies:\n  - {name: collar, mass: 0.2, inertia: [1.0e-3, 2.0e-3, 3.0e-3], position: [0.35, 0.08, -0.05]}\n"
        "joints:\n  - {name: sleeve, type: beam_slider, bodies: [{body: rail, at: 0.37}, collar]}\n");
    const CableMotion m = bent_cable(model, 3, 6);
    expect_rows_match_differences(model, SliderMotion(model, m.q0, m.v0, m.a0));
}


// ---------------------------------------------------------------- dynamics

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
    const double t_end = 0.6, tolerance = 1e-8;
    const Trace trace = run(model, t_end, tolerance, 30);
    const double scale = (0.5 + 1.0) * kG * 0.3;  // the bodies' weight times the collar's drop, about
    double slid = 0.0, tip = 0.0;
    for (size_t r = 0; r < trace.rows.size(); ++r) {
        slid = std::max(slid, trace.at(r, "collar.x") - 0.2);
        tip = std::min(tip, trace.at(r, "rail.node8.y"));
    }
    std::printf("collar on a cantilever over %g s: energy drift %.3g J of %.3g J, |C| %.3g, slid %.3f m, tip lowest %.3f m\n",
                t_end, trace.largest_energy_change(), scale, trace.largest("constraint_position_violation"), slid, tip);
    EXPECT_LT(trace.largest_energy_change(), 10 * tolerance * scale);
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
    const double t_end = 0.4;
    const Trace a = run(flexible, t_end, 1e-8, 20), b = run(rigid, t_end, 1e-10, 20);
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

// ---------------------------------------------------------------- refusals

std::string refusal(const std::string& text) {
    return test::input_error_of([&] { test::scene(text, "slider.yaml"); });
}

// Line 8 of each scene below is the joint's.
std::string slider_scene(const std::string& bodies, const std::string& extra = "",
                         const std::string& flexible = cable("rail", "[0, 0]", "[1, 0]", 4, 1.0e4, 1.0e-3)) {
    return "dimension: planar\nflexible_bodies:\n" + flexible +
           "bodies:\n  - {name: collar, mass: 0.5, inertia: 1.0e-3, position: [0.3, 0]}\n"
           "  - {name: block, mass: 1.0, inertia: 1.0e-2, position: [0.6, 0]}\n"
           "joints:\n  - {name: sleeve, type: beam_slider, bodies: " + bodies + extra + "}\n";
}

TEST(BeamSlider, BadInputNamesTheJointAndTheLine) {
    auto expect_named = [](const std::string& message, const std::string& says) {
        EXPECT_NE(message.find("joint 'sleeve'"), std::string::npos) << message;
        EXPECT_NE(message.find("slider.yaml:8"), std::string::npos) << message;
        EXPECT_NE(message.find(says), std::string::npos) << message;
    };
    EXPECT_EQ(refusal(slider_scene("[{body: rail, at: 0.3}, collar]")), "(accepted)");
    // the collar first, two rigid bodies, the cable at both slots
    expect_named(refusal(slider_scene("[collar, {body: rail, at: 0.3}]")), "[{body: BEAM, at: s0}, COLLAR]");
    expect_named(refusal(slider_scene("[block, collar]")), "first the flexible body");
    expect_named(refusal(slider_scene("[{body: rail, at: 0.3}, {body: rail, at: 0.6}]")), "a rigid body or the ground");
    // a key the type does not have
    const std::string friction = refusal(slider_scene("[{body: rail, at: 0.3}, collar]", ", friction: 0.1"));
    EXPECT_NE(friction.find("unknown key 'friction'"), std::string::npos) << friction;
    EXPECT_NE(friction.find("slider.yaml:8"), std::string::npos) << friction;
    // an axis, which the joint would not use
    const std::string axis = refusal(slider_scene("[{body: rail, at: 0.3}, collar]", ", axis: [1, 0]"));
    EXPECT_NE(axis.find("joint 'sleeve'"), std::string::npos) << axis;
    EXPECT_NE(axis.find("slider.yaml:8"), std::string::npos) << axis;
    EXPECT_NE(axis.find("has no axis"), std::string::npos) << axis;
    // an orientation that is neither free nor tangent, and the sleeve in space
    expect_named(refusal(slider_scene("[{body: rail, at: 0.3}, collar]", ", orientation: sideways")),
                 "'orientation' must be free");
    const std::string spatial = refusal(
        "dimension: spatial\nflexible_bodies:\n" + cable("rail", "[0, 0, 0]", "[1, 0, 0]", 4, 1.0e4, 1.0e-3) +
        "bodies:\n  - {name: collar, mass: 0.5, inertia: [1, 1, 1], position: [0.3, 0, 0]}\n\n"
        "joints:\n  - {name: sleeve, type: beam_slider, bodies: [{body: rail, at: 0.3}, collar], orientation: tangent}\n");
    expect_named(spatial, "planar only");
    // a flexible body without a centre line: the floating-frame body
    const std::string ffrf = refusal(slider_scene(
        "[{body: rail, at: 0.3}, collar]", "",
        "  - {name: rail, type: ffrf_body, from: [0, 0], to: [1, 0], elements: 4, modes: 2, modulus: 1.0e6, "
        "area: 1.0, second_moment: 1.0e-6, density: 1.0}\n"));
    expect_named(ffrf, "flexible body 'rail' (type ffrf_body) has no centre line");
    // through the command line: exit status 2 for bad input
    const std::filesystem::path file =
        test::write_scratch_file("beam_slider", "bad.yaml", slider_scene("[collar, {body: rail, at: 0.3}]"));
    const test::CommandResult r = test::run_mbd("check '" + file.string() + "'");
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    EXPECT_NE(r.err.find("joint 'sleeve'"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("bad.yaml:8"), std::string::npos) << r.err;
}

// A collar given a push towards the free end of a cable clamped at its other end: when its
// closest point passes the end the run stops with an error naming the joint and the time.
TEST(BeamSlider, ACollarThatRunsOffTheBeamStopsTheRunNamingTheJointAndTheTime) {
    const Model model = test::scene(
        "dimension: planar\nflexible_bodies:\n" + cable("rail", "[0, 0]", "[1, 0]", 2, 1.0e4, 1.0e-3) +
            "bodies:\n  - {name: collar, mass: 0.5, inertia: 1.0e-3, position: [0.8, 0], velocity: [2, 0]}\n"
            "joints:\n  - {name: clamp, type: fixed, bodies: [ground, {body: rail, node: 0}]}\n"
            "  - {name: sleeve, type: beam_slider, bodies: [{body: rail, at: 0.8}, collar]}\n",
        "slider.yaml");
    try {
        simulate(model, test::shared_registry(), test::adaptive_run("augmented", "dopri5", 1e-8, 1.0, 0.01),
                 [](const SimulationSample&) { return true; });
        ADD_FAILURE() << "the collar left the cable and the run went on";
    } catch (const DynamicsError& e) {
        const std::string m = e.what();
        std::printf("%s\n", m.c_str());
        EXPECT_NE(m.find("joint 'sleeve'"), std::string::npos) << m;
        EXPECT_NE(m.find("slider.yaml:8"), std::string::npos) << m;
        EXPECT_NE(m.find("left the flexible body"), std::string::npos) << m;
        // the collar at 2 m/s reaches the end 0.2 m away at t = 0.1 s (no force along the cable)
        EXPECT_NEAR(e.time(), 0.1, 1e-3) << m;
    }
}

// Only the augmented formulation takes flexible bodies; the others refuse the scene by name.
TEST(BeamSlider, FormulationsWithoutFlexibleBodiesRefuseTheScene) {
    const Model model = test::scene(slider_scene("[{body: rail, at: 0.3}, collar]"), "slider.yaml");
    for (const std::string formulation : {"embedding", "amalgamated", "hamiltonian"}) {
        SimulationSettings settings = test::adaptive_run(formulation, "dopri5", 1e-8, 0.1, 0.05);
        const std::string message =
            test::input_error_of([&] { check_simulation_method(model, test::shared_registry(), settings); });
        EXPECT_NE(message.find("flexible body 'rail'"), std::string::npos) << formulation << ": " << message;
    }
    SimulationSettings augmented = test::adaptive_run("augmented", "dopri5", 1e-8, 0.1, 0.05);
    EXPECT_NO_THROW(check_simulation_method(model, test::shared_registry(), augmented));
}

}  // namespace
}  // namespace mbd
