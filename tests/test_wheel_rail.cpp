// The wheel_rail joint (plugins/joints/wheel_rail, book Sec. 8.6) against closed forms of the geometry
// of a wheel's tread touching a rail's head, and a wheel rolling and sliding on a crowned rail
// under gravity. The joint's one row is the normal gap g = n . (r_w - r_r); its Jacobian
//     J = [ -n^T | -(x_r x nu)^T | n^T | (x_w x A_j^T n)^T ]
// carries the contact normal and the two contact points' moment arms, so the contact point
// found inside the joint is read back from J (ground columns included when the joint is
// evaluated directly) and compared with the closed forms:
//  - a cylinder (cone angle 0) on a flat head: the contact lies under the axle, g = H - r0;
//  - a cone of angle gamma on a circular crown of radius R, the wheel centre at lateral offset
//    y_c and height H: the cone's bottom generator is a line of slope tan(gamma) in the
//    cross-section, the crown a circle about (0, -R), so the contact sits where the circle's
//    normal is the line's: eta_c = -R sin(gamma) (independent of y_c), the normal is
//    [0, -sin(gamma), cos(gamma)], the wheel's lateral coordinate there is s = eta_c - y_c and
//        g = cos(gamma) (H - r0 + R - y_c tan(gamma)) - R,
//    the rolling radius r0 - s tan(gamma);
//  - a toroidal tread (crown radius rho, the natural spline through points of that circle) on a
//    flat head, the axle rolled by phi about the track: the lowest point of the torus is the
//    lowest point of its centre circle less rho, g = H - (r0 - rho) cos(phi) - rho, at s = -rho sin(phi).
#include <mbd/model_system.hpp>
#include <mbd/sdk/rotation.hpp>
#include <mbd/simulation.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <string>

#include "support/test_support.hpp"

namespace {

using mbd::Vec3;
using mbd::test::g17;
using mbd::test::shared_registry;

const Vec3 kX(1, 0, 0), kY(0, 1, 0), kZ(0, 0, 1);

// A ground rail (frame at the origin, z up, x along the track) and one wheel body, its axle
// along world y at t = 0, with the given wheel: and rail: maps.
std::string contact_scene(const std::string& wheel, const std::string& rail) {
    return "name: wheel-on-rail\ndimension: spatial\nbodies:\n"
           "  - {name: wheel, mass: 10, inertia: [0.5, 0.9, 0.5], position: [0, 0, 0.5]}\n"
           "joints:\n  - {name: contact, type: wheel_rail, bodies: [ground, wheel], point: [0, 0, 0], axis: [0, 0, 1], "
           "x_axis: [1, 0, 0], wheel: " + wheel + ", rail: " + rail + "}\n";
}

struct Evaluation {
    double gap = 0;
    Vec3 n, rail_arm, wheel_arm;  // J blocks: -(x_r x nu) and (x_w x A^T n)
};

// The contact joint evaluated directly with the wheel at `centre`, turned by `A`.
Evaluation evaluate(const mbd::Model& model, const Vec3& centre, const Eigen::Quaterniond& turn) {
    mbd::SpatialBody rail, wheel;
    rail.ground = true;
    wheel.set(centre, mbd::Vec4(turn.w(), turn.x(), turn.y(), turn.z()), Vec3(0.3, -0.2, 0.1), Vec3(0.2, 5.0, -0.1));
    mbd::BodyStates b;
    b.spatial_bodies = {&rail, &wheel};
    mbd::ConstraintEval out;
    out.resize(1, 12);
    model.joints.at(0).joint->evaluate(b, out);
    Evaluation e;
    e.gap = out.C[0];
    e.n = out.J.block<1, 3>(0, 6).transpose();
    e.rail_arm = out.J.block<1, 3>(0, 3).transpose();
    e.wheel_arm = out.J.block<1, 3>(0, 9).transpose();
    EXPECT_NEAR((out.J.block<1, 3>(0, 0).transpose() + e.n).norm(), 0.0, 1e-15);
    return e;
}

// The arms that J must carry for contact points P_r (rail) and P_w (wheel), world axes, with
// the rail as the ground and the wheel turned by A about its centre c.
void expect_arms(const Evaluation& e, const Vec3& n, const Vec3& P_r, const Vec3& P_w, const Vec3& c, const mbd::Mat3& A,
                 double tolerance) {
    EXPECT_LE((e.n - n).norm(), tolerance) << e.n.transpose();
    EXPECT_LE((e.rail_arm + P_r.cross(n)).norm(), tolerance) << e.rail_arm.transpose();
    EXPECT_LE((e.wheel_arm - (A.transpose() * (P_w - c)).cross(A.transpose() * n)).norm(), tolerance)
        << e.wheel_arm.transpose();
}

TEST(WheelRail, ACylinderOnAFlatHeadTouchesUnderItsAxle) {
    const double r0 = 0.45;
    const mbd::Model model = mbd::test::scene(contact_scene("{type: cone, radius: 0.45}", "{type: flat}"));
    double worst = 0;
    for (const Vec3& c : {Vec3(0, 0, 0.5), Vec3(1.7, 0.012, 0.43), Vec3(-3.2, -0.02, 0.451)})
        for (double spin : {0.0, 1.3, -2.9}) {
            const Eigen::Quaterniond turn(Eigen::AngleAxisd(spin, kY));
            const Evaluation e = evaluate(model, c, turn);
            EXPECT_NEAR(e.gap, c.z() - r0, 1e-14);
            // under the axle, on the track's centre line (a line contact: the joint keeps it there)
            const Vec3 P_r(c.x(), 0, 0), P_w(c.x(), 0, c.z() - r0);
            expect_arms(e, kZ, P_r, P_w, c, turn.toRotationMatrix(), 1e-13);
            worst = std::max(worst, std::abs(e.gap - (c.z() - r0)));
        }
    std::cout << "cylinder on flat head: max gap error " << worst << " m\n";
}

TEST(WheelRail, AConeOnACircularCrownTouchesWhereTheClosedFormSays) {
    const double r0 = 0.45, gamma = 0.05, R = 0.3, k = std::tan(gamma);
    const mbd::Model model = mbd::test::scene(
        contact_scene("{type: cone, radius: " + g17(r0) + ", cone_angle: " + g17(gamma) + "}",
                      "{type: arc, radius: " + g17(R) + "}"));
    const Vec3 n(0, -std::sin(gamma), std::cos(gamma));
    double gap_error = 0, worst_radius = 0, best_radius = 1e9;
    for (double y_c : {-0.012, 0.0, 0.004, 0.02})
        for (double lift : {0.0, 0.003, -0.001}) {
            const double H = r0 - R + R / std::cos(gamma) + y_c * k + lift;
            const Vec3 c(0.8, y_c, H);
            const Eigen::Quaterniond turn(Eigen::AngleAxisd(0.7 + 10 * y_c, kY));
            const Evaluation e = evaluate(model, c, turn);
            const double g = std::cos(gamma) * (H - r0 + R - y_c * k) - R;
            EXPECT_NEAR(e.gap, g, 1e-13);
            const double eta_c = -R * std::sin(gamma), s = eta_c - y_c - g * std::sin(gamma);
            const Vec3 P_r(c.x(), eta_c, R * std::cos(gamma) - R);
            const Vec3 P_w = c + s * kY - (r0 - s * k) * kZ;  // on the cone's bottom generator
            ASSERT_LE((P_w - (P_r + g * n)).norm(), 1e-14);  // the closed forms agree with each other
            expect_arms(e, n, P_r, P_w, c, turn.toRotationMatrix(), 1e-12);
            gap_error = std::max(gap_error, std::abs(e.gap - g));
            if (lift == 0.0) {
                const double rolling_radius = r0 - (eta_c - y_c) * k;
                worst_radius = std::max(worst_radius, rolling_radius);
                best_radius = std::min(best_radius, rolling_radius);
            }
        }
    std::cout << "cone on crown: max gap error " << gap_error << " m; rolling radius from " << best_radius << " to "
              << worst_radius << " m over the lateral shifts\n";
}

TEST(WheelRail, ASplineTorusRolledOnAFlatHeadMatchesTheTorus) {
    const double r0 = 0.45, rho = 0.5;
    std::string points = "[";
    for (int k = -24; k <= 24; ++k) {
        const double s = 0.0025 * k;
        points += std::string(k == -24 ? "" : ", ") + "[" + g17(s) + ", " + g17(r0 - rho + std::sqrt(rho * rho - s * s)) + "]";
    }
    points += "]";
    const mbd::Model model = mbd::test::scene(contact_scene("{type: spline, points: " + points + "}", "{type: flat}"));
    double worst = 0;
    for (double phi : {0.0, 0.01, -0.03, 0.04}) {
        const Vec3 c(0.2, -0.004, 0.46);
        const Eigen::Quaterniond turn = Eigen::AngleAxisd(phi, kX) * Eigen::AngleAxisd(0.4, kY);
        const Evaluation e = evaluate(model, c, turn);
        const double g = c.z() - (r0 - rho) * std::cos(phi) - rho;
        EXPECT_NEAR(e.gap, g, 1e-11);
        const Vec3 axle = turn * kY, radial(0, std::sin(phi), -std::cos(phi));
        const double s = -rho * std::sin(phi);
        const Vec3 P_w = c + s * axle + (r0 - rho + std::sqrt(rho * rho - s * s)) * radial;
        const Vec3 P_r = P_w - g * kZ;
        expect_arms(e, kZ, P_r, P_w, c, turn.toRotationMatrix(), 1e-8);
        worst = std::max(worst, std::abs(e.gap - g));
    }
    std::cout << "spline torus on flat head: max gap error " << worst << " m\n";
}

// A wheel on a crowned rail, its axle held horizontal and across the track by a chain of guides
// (sled along x, slider along y, carriage along z, the wheel on a revolute about y): the
// contact keeps the centre at H(y) = H0 + y tan(gamma) (the cone's closed form above), so the
// lateral motion is a block on an incline of slope k = tan(gamma), carried by the masses m_y
// (moving laterally) and m_z (moving vertically):
//     (m_y + m_z k^2) yddot = -m_z g k,   N = m_z (g + k yddot) / cos(gamma),
// along the track the bodies coast, and the wheel spins at its initial rate (no friction: it
// slides as it rolls). The contact's multiplier is -N.
struct CrownedRun {
    double r0 = 0.45, gamma = 0.05, R = 0.3, g = 9.81;
    double m_sled = 1, m_slider = 2, m_carriage = 3, m_wheel = 10;
    double vx = 2.0, vy = 0.1, spin = 3.0;
    double k() const { return std::tan(gamma); }
    double m_y() const { return m_slider + m_carriage + m_wheel; }
    double m_z() const { return m_carriage + m_wheel; }
    double H0() const { return r0 - R + R / std::cos(gamma); }
    double a_y() const { return -m_z() * g * k() / (m_y() + m_z() * k() * k()); }
    double y(double t) const { return vy * t + 0.5 * a_y() * t * t; }
    double N() const { return m_z() * (g + k() * a_y()) / std::cos(gamma); }
    std::string scene() const {
        const std::string H = g17(H0()), vz = g17(k() * vy);
        auto body = [&](const std::string& name, double m, double z, const std::string& v, const std::string& w) {
            return "  - {name: " + name + ", mass: " + g17(m) + ", inertia: [0.5, 0.9, 0.5], position: [0, 0, " +
                   g17(z) + "], velocity: " + v + ", angular_velocity: " + w + "}\n";
        };
        const std::string still = "[0, 0, 0]";
        return "name: crowned-rail\ndimension: spatial\ngravity: [0, 0, -" + g17(g) + "]\nbodies:\n" +
               body("sled", m_sled, H0(), "[" + g17(vx) + ", 0, 0]", still) +
               body("slider", m_slider, H0(), "[" + g17(vx) + ", " + g17(vy) + ", 0]", still) +
               body("carriage", m_carriage, H0(), "[" + g17(vx) + ", " + g17(vy) + ", " + vz + "]", still) +
               body("wheel", m_wheel, H0(), "[" + g17(vx) + ", " + g17(vy) + ", " + vz + "]", "[0, " + g17(spin) + ", 0]") +
               "joints:\n"
               "  - {name: along, type: prismatic, bodies: [ground, sled], point: [0, 0, " + H + "], axis: [1, 0, 0]}\n"
               "  - {name: across, type: prismatic, bodies: [sled, slider], point: [0, 0, " + H + "], axis: [0, 1, 0]}\n"
               "  - {name: up, type: prismatic, bodies: [slider, carriage], point: [0, 0, " + H + "], axis: [0, 0, 1]}\n"
               "  - {name: axle, type: revolute, bodies: [carriage, wheel], point: [0, 0, " + H + "], axis: [0, 1, 0]}\n"
               "  - {name: contact, type: wheel_rail, bodies: [ground, wheel], point: [0, 0, 0], axis: [0, 0, 1], "
               "x_axis: [1, 0, 0], wheel: {type: cone, radius: " + g17(r0) + ", cone_angle: " + g17(gamma) +
               "}, rail: {type: arc, radius: " + g17(R) + "}}\n";
    }
};

TEST(WheelRail, AWheelOnACrownedRailSlidesDownTheConeAsABlockOnAnIncline) {
    const CrownedRun run;
    const mbd::Model model = mbd::test::scene(run.scene());
    mbd::ModelSystem system(model);
    ASSERT_EQ(system.constraint_rows(), 4 * 5 + 1);  // one row for the contact
    mbd::SimulationSettings settings = mbd::test::adaptive_run("augmented", "dopri5", 1e-12, 1.0, 0.01);
    settings.reactions = true;
    const int wheel = model.body_index("wheel");
    const int qw = model.q_offset(wheel), vw = model.v_offset(wheel);
    double position = 0, spin = 0, force = 0, violation = 0, energy = 0, E0 = 0;
    int samples = 0;
    auto energy_of = [&](const mbd::State& s) {
        double E = 0;
        for (int b = 0; b < model.body_count(); ++b) {
            const double m = model.bodies[b].mass;
            const Vec3 v = s.v.segment<3>(model.v_offset(b)), w = s.v.segment<3>(model.v_offset(b) + 3);
            E += 0.5 * m * v.squaredNorm() + 0.5 * w.dot(Vec3(0.5, 0.9, 0.5).cwiseProduct(w)) +
                 m * run.g * s.q[model.q_offset(b) + 2];
        }
        return E;
    };
    mbd::simulate(model, shared_registry(), settings, [&](const mbd::SimulationSample& s) {
        const double t = s.state.t;
        const Vec3 R = s.state.q.segment<3>(qw);
        const Vec3 expected(run.vx * t, run.y(t), run.H0() + run.k() * run.y(t));
        position = std::max(position, (R - expected).norm());
        spin = std::max(spin, (s.state.v.segment<3>(vw + 3) - Vec3(0, run.spin, 0)).norm());
        force = std::max(force, std::abs((*s.lambda)[s.lambda->size() - 1] + run.N()));
        mbd::ConstraintValues cv;
        system.constraints(s.state, cv);
        violation = std::max(violation, std::abs(cv.C[cv.C.size() - 1]));
        if (samples == 0) E0 = energy_of(s.state);
        energy = std::max(energy, std::abs(energy_of(s.state) - E0));
        ++samples;
        return true;
    });
    EXPECT_EQ(samples, 101);
    EXPECT_LE(position, 1e-9);
    EXPECT_LE(spin, 1e-9);
    EXPECT_LE(force, 1e-8 * run.N());
    EXPECT_LE(violation, 1e-10);
    EXPECT_LE(energy, 1e-9 * E0);
    std::cout << "wheel on crowned rail: centre error " << position << " m, spin error " << spin
              << " rad/s, normal force error " << force << " N (N = " << run.N() << "), max |g| " << violation
              << " m, energy drift " << energy << " J of " << E0 << "\n";
}

// A hollow tread (the natural spline through a concave circle of radius rho > R in the
// cross-section: r(s) = r0 + rho - sqrt(rho^2 - s^2)) cradles a crowned head of radius R. The
// wheel rides on a slider (lateral, y) and a carriage (vertical, z), its axle level along y, so
// in the cross-section the hollow's circle, centred at (y, H - r0 - rho), touches the crown's,
// centred at (0, -R), from outside it: the centres are rho - R apart and the contact lies on
// their line, beyond the crown's centre:
//     H(y) = r0 + rho - R - sqrt((rho - R)^2 - y^2),   eta = -y R / (rho - R),   s = -y rho / (rho - R).
// H is least at y = 0: the wheel rocks across the head, the contact sweeping eta over +-3 y at
// rho = 0.4, R = 0.3. Without friction the energy
//     E = m_y ydot^2 / 2 + m_z zdot^2 / 2 + J wdot^2 / 2 + m_z g z     (zdot = H'(y) ydot)
// is constant, which also gives the time to reach any y: t(y) = integral dy / ydot(y).
struct HollowTread {
    double r0 = 0.45, rho = 0.4, R = 0.3, g = 9.81, half_width = 0.12;
    double m_slider = 2, m_carriage = 3, m_wheel = 10, spin = 3.0;
    double vy = 0.2;
    double head_half_width = 0.0;  // > 0: the crown as a spline through its points for |y| <= this
    // convex: a toroidal tread r(s) = r0 - rho + sqrt(rho^2 - s^2) instead, touching the crown
    // from outside (centres R + rho apart): H(y) = r0 - rho - R + sqrt((R + rho)^2 - y^2),
    // eta = y R / (R + rho), and the wheel rolls off the crown
    bool convex = false;
    double m_y() const { return m_slider + m_carriage + m_wheel; }
    double m_z() const { return m_carriage + m_wheel; }
    double H(double y) const {
        if (convex) return r0 - rho - R + std::sqrt((R + rho) * (R + rho) - y * y);
        return r0 + rho - R - std::sqrt((rho - R) * (rho - R) - y * y);
    }
    double H1(double y) const {
        if (convex) return -y / std::sqrt((R + rho) * (R + rho) - y * y);
        return y / std::sqrt((rho - R) * (rho - R) - y * y);
    }
    // the lateral speed at y from the energy (the spin's energy is constant by itself)
    double speed(double y) const {
        const double E = 0.5 * m_y() * vy * vy + m_z() * g * H(0.0);
        return std::sqrt(2.0 * (E - m_z() * g * H(y)) / (m_y() + m_z() * H1(y) * H1(y)));
    }
    // t(y) by Simpson's rule over 2000 panels (the speed stays well above zero)
    double time_to(double y) const {
        const int n = 2000;
        double sum = 1.0 / speed(0.0) + 1.0 / speed(y);
        for (int k = 1; k < n; ++k) sum += (k % 2 ? 4.0 : 2.0) / speed(y * k / n);
        return sum * y / n / 3.0;
    }
    std::string scene() const {
        std::string points = "[";
        for (int k = -24; k <= 24; ++k) {
            const double s = half_width * k / 24;
            const double r = convex ? r0 - rho + std::sqrt(rho * rho - s * s) : r0 + rho - std::sqrt(rho * rho - s * s);
            points += std::string(k == -24 ? "" : ", ") + "[" + g17(s) + ", " + g17(r) + "]";
        }
        points += "]";
        std::string head = "{type: arc, radius: " + g17(R) + "}";
        if (head_half_width > 0.0) {
            head = "{type: spline, points: [";
            for (int k = -12; k <= 12; ++k) {
                const double y = head_half_width * k / 12;
                head += std::string(k == -12 ? "" : ", ") + "[" + g17(y) + ", " + g17(std::sqrt(R * R - y * y) - R) + "]";
            }
            head += "]}";
        }
        const std::string h = g17(H(0.0));
        auto body = [&](const std::string& name, double m, const std::string& v, const std::string& w) {
            return "  - {name: " + name + ", mass: " + g17(m) + ", inertia: [0.5, 0.9, 0.5], position: [0, 0, " + h +
                   "], velocity: " + v + ", angular_velocity: " + w + "}\n";
        };
        const std::string moving = "[0, " + g17(vy) + ", 0]", still = "[0, 0, 0]";
        return "name: hollow-tread\ndimension: spatial\ngravity: [0, 0, -" + g17(g) + "]\nbodies:\n" +
               body("slider", m_slider, moving, still) + body("carriage", m_carriage, moving, still) +
               body("wheel", m_wheel, moving, "[0, " + g17(spin) + ", 0]") +
               "joints:\n"
               "  - {name: across, type: prismatic, bodies: [ground, slider], point: [0, 0, " + h + "], axis: [0, 1, 0]}\n"
               "  - {name: up, type: prismatic, bodies: [slider, carriage], point: [0, 0, " + h + "], axis: [0, 0, 1]}\n"
               "  - {name: axle, type: revolute, bodies: [carriage, wheel], point: [0, 0, " + h + "], axis: [0, 1, 0]}\n"
               "  - {name: contact, type: wheel_rail, bodies: [ground, wheel], point: [0, 0, 0], axis: [0, 0, 1], "
               "x_axis: [1, 0, 0], wheel: {type: spline, points: " + points + "}, rail: " + head + "}\n";
    }
};

TEST(WheelRail, AHollowTreadRocksAcrossTheCrownKeepingItsEnergy) {
    const HollowTread rig;
    const mbd::Model model = mbd::test::scene(rig.scene());
    // (the drift is the integrator's: 4.5e-8, 2.9e-9 and 5.8e-11 J at tol 1e-10, 1e-11, 1e-12)
    const mbd::SimulationSettings settings = mbd::test::adaptive_run("augmented", "dopri5", 1e-12, 1.0, 0.01);
    const int wheel = model.body_index("wheel"), qw = model.q_offset(wheel), vw = model.v_offset(wheel);
    const double J = 0.9;
    double E0 = 0, energy = 0, height = 0, y_min = 0, y_max = 0;
    mbd::simulate(model, shared_registry(), settings, [&](const mbd::SimulationSample& s) {
        const Vec3 R = s.state.q.segment<3>(qw), v = s.state.v.segment<3>(vw);
        const double E = 0.5 * rig.m_y() * v.y() * v.y() + 0.5 * rig.m_z() * v.z() * v.z() +
                         0.5 * J * s.state.v[vw + 4] * s.state.v[vw + 4] + rig.m_z() * rig.g * R.z();
        if (s.state.t == 0.0) E0 = E;
        energy = std::max(energy, std::abs(E - E0));
        height = std::max(height, std::abs(R.z() - rig.H(R.y())));  // the contact stays on both profiles
        y_min = std::min(y_min, R.y());
        y_max = std::max(y_max, R.y());
        return true;
    });
    // the contact swept the head: eta = -3 y over more than 0.1 m of it (the head is 0.6 m wide)
    const double sweep = (y_max - y_min) * rig.R / (rig.rho - rig.R);
    EXPECT_GE(sweep, 0.1);
    EXPECT_LE(height, 1e-8);
    const double kinetic = 0.5 * rig.m_y() * rig.vy * rig.vy;
    EXPECT_LE(energy, 1e-9 * kinetic);
    std::cout << "hollow tread on crown: contact swept " << sweep << " m across the head; max |z - H(y)| " << height
              << " m, energy drift " << energy << " J of a lateral kinetic energy " << kinetic << " J\n";
}

TEST(WheelRail, ATreadThatRunsOffItsProfileStopsTheRunNamingWhereAndWhen) {
    HollowTread rig;
    rig.vy = 0.6;  // swings past y = 0.03, where s = -4 y leaves the tread's points (|s| <= 0.12)
    const double y_edge = rig.half_width * (rig.rho - rig.R) / rig.rho, t_edge = rig.time_to(y_edge);
    ASSERT_TRUE(std::isfinite(t_edge));
    const mbd::Model model = mbd::test::scene(rig.scene());
    const mbd::SimulationSettings settings = mbd::test::adaptive_run("augmented", "dopri5", 1e-11, 1.0, 0.01);
    try {
        mbd::simulate(model, shared_registry(), settings, [](const mbd::SimulationSample&) { return true; });
        FAIL() << "the run went on with the contact off the tread";
    } catch (const mbd::DynamicsError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("joint 'contact' (type wheel_rail, test.yaml:"), std::string::npos) << message;
        EXPECT_NE(message.find("left its domain at t = "), std::string::npos) << message;
        EXPECT_NE(message.find("outside the wheel's profile (s from -0.12 to 0.12 m)"), std::string::npos) << message;
        // the run stops at the first evaluation that finds the contact outside, a stage of the
        // step that crosses the edge: within one step (here about 2 ms) after the crossing
        EXPECT_GE(e.time(), t_edge - 1e-4) << message;
        EXPECT_LE(e.time(), t_edge + 5e-3) << message;
        EXPECT_NE(message.find("the contact point is at s = -0.12"), std::string::npos) << message;
        std::cout << "tread off its profile: stopped at t = " << e.time() << " s; the energy puts the edge at t = "
                  << t_edge << " s\n" << message << "\n";
    }
}

TEST(WheelRail, AContactThatRunsOffANarrowHeadStopsTheRunNamingHowFar) {
    // a toroidal tread (convex: a point contact up to the head's ends, where a natural spline
    // straightens) rolling off a crown given as a spline over |y| <= 0.06: eta = 3 y / 8 reaches
    // 0.06 at y = 0.16 (s = -0.1, still on the tread)
    HollowTread rig;
    rig.convex = true;
    rig.vy = 0.6;
    rig.head_half_width = 0.06;
    const double y_edge = rig.head_half_width * (rig.R + rig.rho) / rig.R, t_edge = rig.time_to(y_edge);
    const mbd::Model model = mbd::test::scene(rig.scene());
    try {
        mbd::simulate(model, shared_registry(), mbd::test::adaptive_run("augmented", "dopri5", 1e-11, 1.0, 0.01),
                      [](const mbd::SimulationSample&) { return true; });
        FAIL() << "the run went on with the contact off the head";
    } catch (const mbd::DynamicsError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("left its domain at t = "), std::string::npos) << message;
        EXPECT_NE(message.find("the contact point is at y = 0.06"), std::string::npos) << message;
        EXPECT_NE(message.find("outside the head's profile (y from -0.06 to 0.06 m)"), std::string::npos) << message;
        // the arc's closed form only roughly: the natural spline straightens towards its ends (its
        // curvature goes to zero there), so the wheel reaches the edge a little early (2.4 ms)
        EXPECT_NEAR(e.time(), t_edge, 5e-3) << message;
        std::cout << "contact off a narrow head: stopped at t = " << e.time() << " s; the energy puts the edge at t = "
                  << t_edge << " s\n";
    }
}

TEST(WheelRail, TheExampleWheelsetPushedSidewaysStopsWhereItsWheelLeavesTheRail) {
    // the case: 3 m/s sideways carried the wheelset 2.27 m aside with exit 0, the cones
    // (unbounded then) touching the crowns far along their axle; the treads (default width
    // 2 r0 = 0.9 m) end at |s| = 0.45 m
    const std::string text = mbd::test::read_text(mbd::test::scene_path("examples/spatial-wheelset.yaml"));
    const mbd::Model model = mbd::test::scene(mbd::test::replaced(text, "velocity: [10, 0.02, 0]", "velocity: [10, 3, 0]"));
    try {
        mbd::simulate(model, shared_registry(), mbd::test::adaptive_run("augmented", "dop853", 1e-8, 1.0, 0.01),
                      [](const mbd::SimulationSample&) { return true; });
        FAIL() << "the run went on with the wheelset off the rails";
    } catch (const mbd::DynamicsError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("joint 'right' (type wheel_rail, test.yaml:"), std::string::npos) << message;
        EXPECT_NE(message.find("outside the wheel's profile (s from -0.45 to 0.45 m)"), std::string::npos) << message;
        // s = eta - y (eta the contact across the crown, |eta| < R = 0.3 m; y the wheel's shift), so
        // the edge needs |y| >= 0.15 m, at a lateral speed of at most the initial 3 m/s
        EXPECT_GE(3.0 * e.time(), 0.45 - 0.3) << message;
        EXPECT_LE(e.time(), 0.5) << message;
        std::cout << "wheelset at 3 m/s sideways: " << message << "\n";
    }
}

// A cylinder rocking on a crown: the contact runs to and fro across the rail's head. A cylinder
// of radius r0 whose axle, through its centre at height H, is tilted by phi about the track
// touches a crown of radius R (centre line at depth R under the top) where the distance from
// the crown's centre to the axle, (H + R) cos(phi), is r0 + R, so
//     H(phi) = (r0 + R) / cos(phi) - R,   the contact at the lateral position eta = -R sin(phi),
// with the normal (0, -sin(phi), cos(phi)). H has its least value at phi = 0: under gravity the
// wheel, on a revolute about the track on a carriage free to move up (and a sled coasting along
// the track), rocks about the upright. Nothing dissipates (the contact is frictionless), so the
// energy is constant; the contact's normal is read from the wheel's columns of J.
TEST(WheelRail, ACylinderRockingOnACrownMovesTheContactAcrossTheHead) {
    const double r0 = 0.45, R = 0.3, g = 9.81, rocking = 1.4;
    const std::string H = g17(r0);
    auto body = [&](const std::string& name, double m, const std::string& w) {
        return "  - {name: " + name + ", mass: " + g17(m) + ", inertia: [0.5, 0.9, 0.5], position: [0, 0, " + H +
               "], velocity: [2, 0, 0], angular_velocity: " + w + "}\n";
    };
    const std::string yaml =
        "name: rocking-wheel\ndimension: spatial\ngravity: [0, 0, -" + g17(g) + "]\nbodies:\n" + body("sled", 1, "[0, 0, 0]") +
        body("carriage", 3, "[0, 0, 0]") + body("wheel", 10, "[" + g17(rocking) + ", 0, 0]") +
        "joints:\n"
        "  - {name: along, type: prismatic, bodies: [ground, sled], point: [0, 0, " + H + "], axis: [1, 0, 0]}\n"
        "  - {name: up, type: prismatic, bodies: [sled, carriage], point: [0, 0, " + H + "], axis: [0, 0, 1]}\n"
        "  - {name: rock, type: revolute, bodies: [carriage, wheel], point: [0, 0, " + H + "], axis: [1, 0, 0]}\n"
        "  - {name: contact, type: wheel_rail, bodies: [ground, wheel], point: [0, 0, 0], axis: [0, 0, 1], "
        "x_axis: [1, 0, 0], wheel: {type: cone, radius: " + g17(r0) + "}, rail: {type: arc, radius: " + g17(R) + "}}\n";
    const mbd::Model model = mbd::test::scene(yaml);
    mbd::ModelSystem system(model);
    const int wheel = model.body_index("wheel"), carriage = model.body_index("carriage");
    double height = 0, normal = 0, energy = 0, E0 = 0, east = 0, west = 0;
    int samples = 0;
    mbd::simulate(model, shared_registry(), mbd::test::adaptive_run("augmented", "dop853", 1e-11, 1.0, 0.01),
                  [&](const mbd::SimulationSample& s) {
                      const mbd::Mat3 A = mbd::rotation_from_euler_parameters(s.state.q.segment<4>(model.q_offset(wheel) + 3));
                      const Vec3 axle = A * kY;
                      const double phi = std::atan2(axle.z(), axle.y());
                      height = std::max(height, std::abs(s.state.q[model.q_offset(carriage) + 2] - ((r0 + R) / std::cos(phi) - R)));
                      mbd::ConstraintValues cv;
                      system.constraints(s.state, cv);
                      Vec3 n = Vec3::Zero();
                      for (int c = 0; c < 3; ++c) n[c] = cv.J.coeff(cv.J.rows() - 1, model.v_offset(wheel) + c);
                      normal = std::max(normal, (n - Vec3(0, -std::sin(phi), std::cos(phi))).norm());
                      const double eta = R * n.y();  // the contact's lateral position on the crown
                      east = std::max(east, eta);
                      west = std::min(west, eta);
                      const double E = system.kinetic_energy(s.state) + system.potential_energy(s.state);
                      if (samples++ == 0) E0 = E;
                      energy = std::max(energy, std::abs(E - E0));
                      return true;
                  });
    std::cout << "cylinder rocking on a crown, 1 s: contact from " << west << " to " << east << " m across the head, "
              << "height error " << height << " m, normal error " << normal << ", energy drift " << energy << " J of "
              << E0 << "\n";
    EXPECT_EQ(samples, 101);
    EXPECT_LT(west, -0.02);  // both sides of the crown's top
    EXPECT_GT(east, 0.02);
    EXPECT_LT(height, 1e-9);
    EXPECT_LT(normal, 1e-9);
    EXPECT_LT(energy, 1e-9 * E0);
}

TEST(WheelRail, BadInputIsNamed) {
    const std::string good = contact_scene("{type: cone, radius: 0.45, cone_angle: 0.05}", "{type: arc, radius: 0.3}");
    auto error_of = [&](const std::string& text) {
        try {
            mbd::test::scene(text);
        } catch (const std::exception& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    auto contains = [](const std::string& text, const std::string& part) {
        return text.find(part) != std::string::npos ? testing::AssertionSuccess()
                                                    : testing::AssertionFailure() << text;
    };
    std::string planar = mbd::test::replaced(good, "dimension: spatial", "dimension: planar");
    planar = mbd::test::replaced(planar, "inertia: [0.5, 0.9, 0.5], position: [0, 0, 0.5]", "inertia: 0.5, position: [0, 0.5]");
    planar = mbd::test::replaced(planar, "point: [0, 0, 0], axis: [0, 0, 1], x_axis: [1, 0, 0]", "point: [0, 0]");
    EXPECT_TRUE(contains(error_of(planar), "joint 'contact': wheel_rail is a spatial joint"));
    EXPECT_TRUE(contains(error_of(mbd::test::replaced(good, "type: arc", "type: crown")),
                         "unknown rail profile type 'crown'"));
    EXPECT_TRUE(contains(error_of(mbd::test::replaced(good, "type: arc, radius: 0.3", "type: flat")),
                         "a conical wheel on a flat head"));
    EXPECT_TRUE(contains(error_of(mbd::test::replaced(good, "{type: cone, radius: 0.45, cone_angle: 0.05}",
                                                      "{type: spline, points: [[0, 0.45], [0.01, 0.449], [0.01, 0.448]]}")),
                         "wheel_rail 'contact': 'wheel.points': the lateral coordinates must be strictly increasing"));
    EXPECT_TRUE(contains(error_of(mbd::test::replaced(good, "{type: cone, radius: 0.45, cone_angle: 0.05}",
                                                      "{type: spline, points: [[0, 0.45], [0.01, 0.449]]}")),
                         "at least 3 points"));
    EXPECT_TRUE(contains(error_of(mbd::test::replaced(good, "radius: 0.45", "radius: -0.45")), "'radius' must be positive"));
    EXPECT_TRUE(contains(error_of(mbd::test::replaced(good, "x_axis: [1, 0, 0]", "x_axis: [1, 0, 0], axle: [0, 0, 0]")),
                         "'axle' must not be zero"));
}

}  // namespace
