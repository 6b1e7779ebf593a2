// The beam_slider joint (core evaluation/beam_slider.hpp, docs/scene-format.md): a collar's point
// sliding without friction along the centre line of an ANCF body. Its rows here: central
// differences of C (s* re-solved at each probe) for the Jacobian, and of C along a smooth motion
// for gamma (Cddot = J vdot - gamma), at a deformed, moving state whose collar point is on the
// curve and leaves it at a non-zero rate (planar, the sleeve's angle row, the shear-deformable
// beam, spatial); and refusals of bad input naming the joint and file:line, and a collar that runs
// off the beam. Its motion: tests/test_beam_slider_motion.cpp.
#include "support/beam_slider_scenes.hpp"
#include "support/input_files.hpp"
#include "support/test_support.hpp"

#include <mbd/model_system.hpp>
#include <mbd/sdk/rotation.hpp>
#include <mbd/sdk/text.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace mbd {
namespace {

using test::cable;
constexpr double kPi = test::kSliderPi;

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
