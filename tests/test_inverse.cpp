// Inverse dynamics (issue 6): the Ipopt inverse plugin against the closed forms of
// book Sec. 4.7 (Eq. 4.35, two-link arm) and Sec. 6.13 (slider crank), the weighted
// pseudo-inverse for redundant actuation, bounds, forward-dynamics replay, errors.
#include "support/test_support.hpp"

#include <mbd/scene.hpp>
#include <mbd/simulation.hpp>
#include <mbd/statics_analysis.hpp>
#include <mbd/kit/formulation.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>

namespace {

using mbd::test::g17;
using mbd::test::scene;

using mbd::test::shared_registry;

std::vector<mbd::InverseSample> inverse(const mbd::Model& model, double t_end, double step) {
    std::vector<mbd::InverseSample> out;
    mbd::run_inverse(model, shared_registry(), t_end, step, [&](const mbd::InverseSample& s, mbd::System&) {
        out.push_back(s);
        return true;
    });
    return out;
}

// ---------------------------------------------------------------- two-link arm, book Sec. 4.7

struct Arm {
    double lO2 = 0.3, lA2 = 0.2, lA3 = 0.25, l3 = 0.5;  // l2 = lO2 + lA2
    double m2 = 2.0, m3 = 1.2, J2 = 0.05, J3 = 0.03, g = 9.81;
    // shoulder theta2 = a0 + a1 sin(w1 t); elbow (relative) phi = b0 + b1 sin(w2 t + pi/2)
    double a0 = 0.3, a1 = 0.6, w1 = 2.0, b0 = 0.8, b1 = 0.5, w2 = 3.0;
    double l2() const { return lO2 + lA2; }

    void angles(double t, double th[2], double thd[2], double thdd[2]) const {
        th[0] = a0 + a1 * std::sin(w1 * t);
        thd[0] = a1 * w1 * std::cos(w1 * t);
        thdd[0] = -a1 * w1 * w1 * std::sin(w1 * t);
        const double p = b0 + b1 * std::cos(w2 * t), pd = -b1 * w2 * std::sin(w2 * t), pdd = -b1 * w2 * w2 * std::cos(w2 * t);
        th[1] = th[0] + p;
        thd[1] = thd[0] + pd;
        thdd[1] = thdd[0] + pdd;
    }
    // Eq. 4.35e, 4.35f: M2 acts on body 2 only, M3 on body 3 only
    void book_torques(double t, double& M2, double& M3) const {
        double th[2], thd[2], thdd[2];
        angles(t, th, thd, thdd);
        const double c2 = std::cos(th[0]), s2 = std::sin(th[0]), c3 = std::cos(th[1]), s3 = std::sin(th[1]);
        const double ax2 = lO2 * (-s2 * thdd[0] - c2 * thd[0] * thd[0]), ay2 = lO2 * (c2 * thdd[0] - s2 * thd[0] * thd[0]);
        const double ax3 = l2() * (-s2 * thdd[0] - c2 * thd[0] * thd[0]) + lA3 * (-s3 * thdd[1] - c3 * thd[1] * thd[1]);
        const double ay3 = l2() * (c2 * thdd[0] - s2 * thd[0] * thd[0]) + lA3 * (c3 * thdd[1] - s3 * thd[1] * thd[1]);
        const double A51 = lO2 * s2, A52 = -lO2 * c2, A53 = lA2 * s2, A54 = -lA2 * c2, A63 = lA3 * s3, A64 = -lA3 * c3;
        M2 = J2 * thdd[0] - A51 * m2 * ax2 - A52 * (m2 * ay2 + m2 * g) - (A51 + A53) * m3 * ax3 -
             (A52 + A54) * (m3 * ay3 + m3 * g);
        M3 = J3 * thdd[1] - A63 * m3 * ax3 - A64 * (m3 * ay3 + m3 * g);
    }

    std::string yaml(const std::string& actuators, bool driven = true, const std::string& torques = "") const {
        double th[2], thd[2], thdd[2];
        angles(0.0, th, thd, thdd);
        const double c2 = std::cos(th[0]), s2 = std::sin(th[0]), c3 = std::cos(th[1]), s3 = std::sin(th[1]);
        const double Ax = l2() * c2, Ay = l2() * s2;
        std::ostringstream s;
        s << "dimension: planar\ngravity: [0, " << -g << "]\nbodies:\n"
          << "  - {name: upper, mass: " << m2 << ", inertia: " << J2 << ", position: [" << g17(lO2 * c2) << ", "
          << g17(lO2 * s2) << "], angle: " << g17(th[0]) << ", velocity: [" << g17(-lO2 * s2 * thd[0]) << ", "
          << g17(lO2 * c2 * thd[0]) << "], angular_velocity: " << g17(thd[0]) << "}\n"
          << "  - {name: fore, mass: " << m3 << ", inertia: " << J3 << ", position: [" << g17(Ax + lA3 * c3) << ", "
          << g17(Ay + lA3 * s3) << "], angle: " << g17(th[1]) << ", velocity: ["
          << g17(-l2() * s2 * thd[0] - lA3 * s3 * thd[1]) << ", " << g17(l2() * c2 * thd[0] + lA3 * c3 * thd[1])
          << "], angular_velocity: " << g17(thd[1]) << "}\n"
          << "joints:\n"
          << "  - {name: shoulder, type: revolute, bodies: [ground, upper], point: [0, 0]}\n"
          << "  - {name: elbow, type: revolute, bodies: [upper, fore], point: [" << g17(Ax) << ", " << g17(Ay) << "]}\n";
        if (driven)
            s << "drivers:\n"
              << "  - {name: d_shoulder, joint: shoulder, motion: {type: harmonic, offset: " << a0 << ", amplitude: " << a1
              << ", frequency: " << w1 << "}}\n"
              << "  - {name: d_elbow, joint: elbow, motion: {type: harmonic, offset: " << b0 << ", amplitude: " << b1
              << ", frequency: " << w2 << ", phase: " << g17(M_PI / 2) << "}}\n";
        if (!torques.empty()) s << "forces:\n" << torques;
        if (!actuators.empty()) s << "actuators:\n" << actuators;
        return s.str();
    }
};

const std::string kArmActuators = "  - {name: t_shoulder, joint: shoulder}\n  - {name: t_elbow, joint: elbow}\n";

// Joint torques: the elbow torque acts +t_elbow on the forearm and -t_elbow on the
// upper arm, so the book's (absolute) M3 = t_elbow and M2 = t_shoulder - t_elbow.
TEST(InverseTwoLinkArm, MatchesEq435) {
    const Arm arm;
    const mbd::Model model = scene(arm.yaml(kArmActuators));
    const auto samples = inverse(model, 2.0, 0.05);
    ASSERT_EQ(samples.size(), 41u);
    for (const auto& s : samples) {
        double M2, M3;
        arm.book_torques(s.state.t, M2, M3);
        EXPECT_EQ(s.method, "exact");
        EXPECT_NEAR(s.efforts[1], M3, 1e-8) << "t = " << s.state.t;
        EXPECT_NEAR(s.efforts[0] - s.efforts[1], M2, 1e-8) << "t = " << s.state.t;
    }
}

// Fully actuated: the efforts are the augmented formulation's driver multipliers,
// tau = -lambda_d, from the KKT system [M J^T; J 0] [a; lambda] = [Q; gamma].
TEST(InverseTwoLinkArm, EffortsEqualMinusDriverMultipliersOfTheKkt) {
    const Arm arm;
    const mbd::Model model = scene(arm.yaml(kArmActuators));
    mbd::run_inverse(model, shared_registry(), 1.0, 0.25, [&](const mbd::InverseSample& s, mbd::System& sys) {
        mbd::ConstraintValues cv;
        sys.constraints(s.state, cv, true);
        Eigen::VectorXd Q;
        sys.generalized_forces(s.state, Q);
        const int nv = sys.nv(), m = static_cast<int>(cv.C.size());
        Eigen::MatrixXd K = Eigen::MatrixXd::Zero(nv + m, nv + m);
        K.topLeftCorner(nv, nv) = Eigen::MatrixXd(sys.mass_matrix());
        K.topRightCorner(nv, m) = Eigen::MatrixXd(cv.J).transpose();
        K.bottomLeftCorner(m, nv) = Eigen::MatrixXd(cv.J);
        Eigen::VectorXd rhs(nv + m);
        rhs << Q, cv.gamma;
        const Eigen::VectorXd x = K.fullPivLu().solve(rhs);
        EXPECT_NEAR(s.efforts[0], -x[nv + m - 2], 1e-8);
        EXPECT_NEAR(s.efforts[1], -x[nv + m - 1], 1e-8);
        return true;
    });
}

// Three actuators on a 2-DOF arm (two on the shoulder with weights 1 and 3, one on
// the elbow): the minimum weighted effort splits the shoulder torque T = M2 + M3 as
// tau1 = 3/4 T, tau2 = 1/4 T (pseudo-inverse solution); the elbow carries M3.
TEST(InverseRedundant, WeightedPseudoInverseSolution) {
    const Arm arm;
    const std::string acts = "  - {name: s1, joint: shoulder, weight: 1}\n  - {name: s2, joint: shoulder, weight: 3}\n"
                             "  - {name: e, joint: elbow}\n";
    const auto samples = inverse(scene(arm.yaml(acts)), 1.0, 0.1);
    for (const auto& s : samples) {
        double M2, M3;
        arm.book_torques(s.state.t, M2, M3);
        EXPECT_EQ(s.method, "pseudo-inverse");
        EXPECT_NEAR(s.efforts[0], 0.75 * (M2 + M3), 1e-8);
        EXPECT_NEAR(s.efforts[1], 0.25 * (M2 + M3), 1e-8);
        EXPECT_NEAR(s.efforts[2], M3, 1e-8);
    }
}

TEST(InverseRedundant, BoundsActiveSolveTheQp) {
    const Arm arm;
    // s2 limited to |tau| <= 0.5: the rest goes to s1 (the weighted QP's solution)
    const std::string acts = "  - {name: s1, joint: shoulder, weight: 1}\n"
                             "  - {name: s2, joint: shoulder, weight: 3, bounds: [-0.5, 0.5]}\n"
                             "  - {name: e, joint: elbow}\n";
    const auto samples = inverse(scene(arm.yaml(acts)), 1.0, 0.1);
    int active = 0;
    for (const auto& s : samples) {
        double M2, M3;
        arm.book_torques(s.state.t, M2, M3);
        const double T = M2 + M3;
        const double s2 = std::clamp(0.25 * T, -0.5, 0.5);
        EXPECT_NEAR(s.efforts[1], s2, 1e-6);
        EXPECT_NEAR(s.efforts[0] + s.efforts[1], T, 1e-8);
        EXPECT_NEAR(s.efforts[2], M3, 1e-8);
        active += s.bounds_active;
    }
    EXPECT_GT(active, 0);
}

TEST(InverseErrors, InfeasibleBoundsReportTheFirstTime) {
    const Arm arm;
    const std::string acts = "  - {name: t_shoulder, joint: shoulder}\n  - {name: t_elbow, joint: elbow, bounds: [-0.1, 0.1]}\n";
    try {
        inverse(scene(arm.yaml(acts)), 1.0, 0.1);
        FAIL() << "no error";
    } catch (const mbd::DynamicsError& e) {
        EXPECT_NEAR(e.time(), 0.0, 1e-12);
        EXPECT_NE(std::string(e.what()).find("t_elbow"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("outside its bounds"), std::string::npos) << e.what();
    }
    // under-actuated: one actuator for two degrees of freedom
    try {
        inverse(scene(arm.yaml("  - {name: t_shoulder, joint: shoulder}\n")), 1.0, 0.1);
        FAIL() << "no error";
    } catch (const mbd::DynamicsError& e) {
        EXPECT_NE(std::string(e.what()).find("cannot produce the prescribed motion"), std::string::npos) << e.what();
    }
}

TEST(InverseErrors, BadActuatorInput) {
    const Arm arm;
    auto expect = [&](const std::string& acts, const std::string& where, const std::string& text) {
        try {
            scene(arm.yaml(acts), "arm.yaml");
            FAIL() << "no error for " << text;
        } catch (const mbd::InputError& e) {
            EXPECT_EQ(e.where(), where) << e.what();
            EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
        }
    };
    expect("  - {name: t, joint: wrist}\n", "arm.yaml:13", "undefined joint 'wrist'");
    expect("  - {name: t, joint: elbow, bounds: [2, 1]}\n", "arm.yaml:13", "infeasible");
    expect("  - {name: t, joint: elbow, weight: 0}\n", "arm.yaml:13", "'weight' must be positive");
}

// ---------------------------------------------------------------- slider crank, book Sec. 6.13

std::string slider_crank(const std::string& actuator_joint) {
    const double l2 = 0.15, l3 = 0.5, th2 = 0.5, w = 8.0;
    const double th3 = std::asin(-(l2 / l3) * std::sin(th2));
    const double Ax = l2 * std::cos(th2), Ay = l2 * std::sin(th2), Bx = Ax + l3 * std::cos(th3);
    std::ostringstream s;
    s << "dimension: planar\ngravity: [0, -9.81]\nbodies:\n"
      << "  - {name: crank, mass: 1.2, inertia: 0.01, position: [" << g17(Ax / 2) << ", " << g17(Ay / 2)
      << "], angle: " << th2 << "}\n"
      << "  - {name: rod, mass: 2.5, inertia: 0.06, position: [" << g17(Ax + 0.2 * std::cos(th3)) << ", "
      << g17(Ay + 0.2 * std::sin(th3)) << "], angle: " << g17(th3) << "}\n"
      << "  - {name: slider, mass: 0.8, inertia: 0.002, position: [" << g17(Bx) << ", 0]}\n"
      << "joints:\n"
      << "  - {name: O, type: revolute, bodies: [ground, crank], point: [0, 0]}\n"
      << "  - {name: A, type: revolute, bodies: [crank, rod], point: [" << g17(Ax) << ", " << g17(Ay) << "]}\n"
      << "  - {name: B, type: revolute, bodies: [rod, slider], point: [" << g17(Bx) << ", 0]}\n"
      << "  - {name: guide, type: prismatic, bodies: [ground, slider], point: [0, 0], axis: [1, 0]}\n"
      << "drivers:\n  - {name: motor, joint: O, motion: {type: linear, initial: " << th2 << ", rate: " << w << "}}\n"
      << "actuators:\n  - {name: effort, joint: " << actuator_joint << "}\n";
    return s.str();
}

// The same crank-driven motion produced by a crank torque M2 or by a slider force F4:
// M2 = -F4 l2 [sin th2 - cos th2 tan th3] (book Sec. 6.13, L9497; virtual work).
TEST(InverseSliderCrank, CrankTorqueAndSliderForceSatisfySec613) {
    const double l2 = 0.15;
    const auto torque = inverse(scene(slider_crank("O")), 0.7, 0.01);
    const auto force = inverse(scene(slider_crank("guide")), 0.7, 0.01);
    ASSERT_EQ(torque.size(), force.size());
    int checked = 0;
    for (size_t k = 0; k < torque.size(); ++k) {
        const double th2 = torque[k].state.q[2], th3 = torque[k].state.q[5];
        const double factor = l2 * (std::sin(th2) - std::cos(th2) * std::tan(th3));
        const double M2 = torque[k].efforts[0], F4 = force[k].efforts[0];
        EXPECT_NEAR(M2, -F4 * factor, 1e-8 * (1 + std::abs(M2))) << "t = " << torque[k].state.t;
        if (std::abs(factor) > 0.05) ++checked;
    }
    EXPECT_GT(checked, 20);
}

// ---------------------------------------------------------------- forward replay

// The computed efforts, applied as spline time functions (two point torques per
// joint: +tau on the outer body, -tau on the inner) to the undriven arm, reproduce
// the prescribed motion. Allowed deviation 1e-5 rad after 1 s: the efforts are
// sampled every 2 ms and interpolated by a natural cubic spline (error ~ h^4 |tau''''|
// ~ 1e-9 N m, plus its end effects) and the open-loop arm amplifies errors over time.
TEST(InverseReplay, EffortsReproduceTheMotionInForwardDynamics) {
    const Arm arm;
    const double h = 0.002, t_end = 1.0;
    const auto samples = inverse(scene(arm.yaml(kArmActuators)), t_end, h);
    auto table = [&](auto value) {
        std::ostringstream s;
        s << "{type: spline, table: [";
        for (size_t k = 0; k < samples.size(); ++k)
            s << (k ? ", " : "") << "[" << g17(samples[k].state.t) << ", " << g17(value(samples[k])) << "]";
        s << "]}";
        return s.str();
    };
    const std::string up = table([](const mbd::InverseSample& s) { return s.efforts[0] - s.efforts[1]; });
    const std::string fo = table([](const mbd::InverseSample& s) { return s.efforts[1]; });
    const std::string torques = "  - {name: on_upper, type: point_torque, body: upper, torque: " + up + "}\n" +
                                "  - {name: on_fore, type: point_torque, body: fore, torque: " + fo + "}\n";
    const mbd::Model free_arm = scene(arm.yaml("", false, torques));
    mbd::SimulationSettings settings;
    settings.t_end = t_end;
    settings.output_step = 0.1;
    settings.integration.tolerance = 1e-11;
    settings.progress = false;
    double worst = 0.0;
    mbd::simulate(free_arm, shared_registry(), settings, [&](const mbd::SimulationSample& s) {
        double th[2], thd[2], thdd[2];
        arm.angles(s.state.t, th, thd, thdd);
        worst = std::max({worst, std::abs(s.state.q[2] - th[0]), std::abs(s.state.q[5] - th[1])});
        return true;
    });
    EXPECT_LT(worst, 1e-5);
    std::cout << "replay: max angle deviation " << worst << " rad\n";
}

// ---------------------------------------------------------------- CLI

TEST(InverseCli, WritesEffortsCsvWithReactions) {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / "mbd_inverse_cli";
    std::filesystem::create_directories(dir);
    const Arm arm;
    const std::filesystem::path in = dir / "arm.yaml", out = dir / "efforts.csv";
    std::ofstream(in) << arm.yaml(kArmActuators);
    const auto r = mbd::test::run_mbd("inverse " + in.string() + " --t-end 0.5 --step 0.1 --output " + out.string() +
                                      " --reactions");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::ifstream csv(out);
    std::string header, first;
    std::getline(csv, header);
    std::getline(csv, first);
    EXPECT_EQ(header, "t,t_shoulder,t_elbow,shoulder.fx,shoulder.fy,shoulder.tz,elbow.fx,elbow.fy,elbow.tz");
    double M2, M3;
    arm.book_torques(0.0, M2, M3);
    std::stringstream row(first);
    std::string cell;
    std::vector<double> v;
    while (std::getline(row, cell, ',')) v.push_back(std::stod(cell));
    ASSERT_EQ(v.size(), 9u);
    EXPECT_NEAR(v[2], M3, 1e-8);
    EXPECT_NEAR(v[1], M2 + M3, 1e-8);
}


// The shipped example (scenes/examples/inverse-pendulum.yaml, the scene docs/user-guide.md and
// docs/statics.md let a user try `mbd inverse` on): a uniform rod (m = 2 kg, l = 1 m) swung about
// the downward vertical by phi(t) = A sin(w t) needs the pin torque of Euler's equation about the
// pin, tau = (m l^2 / 3) phi'' + m g (l/2) sin(phi). A wrong sign of the gravity term, the
// centroidal instead of the pin's inertia, or an effort of the wrong body would each miss by O(1).
TEST(InverseExample, PendulumTorqueIsTheClosedForm) {
    const auto folder = mbd::test::scratch("inverse_example");
    const auto out = folder / "efforts.csv";
    const auto scene_file = mbd::test::scene_path("examples/inverse-pendulum.yaml");
    const auto r = mbd::test::run_mbd("inverse " + scene_file.string() + " --t-end 2 --step 0.02 --output " +
                                      out.string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const mbd::test::Csv csv = mbd::test::read_csv(out);
    const int motor = csv.column("motor");
    ASSERT_GE(motor, 0);
    ASSERT_EQ(csv.rows.size(), 101u);
    const double m = 2.0, l = 1.0, g = 9.81, A = 0.6, w = 3.0;
    for (const auto& row : csv.rows) {
        const double t = row[0];
        const double phi = A * std::sin(w * t), acceleration = -A * w * w * std::sin(w * t);
        EXPECT_NEAR(row[motor], m * l * l / 3.0 * acceleration + m * g * l / 2.0 * std::sin(phi), 1e-9) << "t = " << t;
    }
}

}  // namespace
