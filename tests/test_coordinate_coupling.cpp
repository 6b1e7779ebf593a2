// The coordinate_coupling joint (plugins/joints/coordinate_coupling) against a closed form that no
// formulation computes. A wheel a (axial moment I_a) turned by a constant torque T about a fixed
// vertical axle drives, through two couplings, a wheel b on its own axle (q_b = -2 q_a, a gear
// ratio without gear geometry) and a slider of mass M on a horizontal rail (x = 0.05 q_a, a rack).
// Lagrange with q_a the one coordinate: (I_a + 4 I_b + 0.05^2 M) q_a'' = T, so from rest (wheel b turns
// 1.9 rad in 1 s, within the half turn a coupled angle may go from its start)
//     q_a = T t^2 / (2 I_eff),  q_b = -2 q_a,  x = 0.05 q_a.
// The couplings carry what drives the followers: on wheel b the moment I_b q_b'' about its axle,
// on the slider the force M x'' along the rail; and on the leader the moment that does the same
// virtual work with the opposite sign: -multiplier times the follower's (virtual work of an ideal
// constraint is zero). The Jacobian itself is checked by finite differences in
// tests/test_joint_derivatives.cpp (scenes/examples/spatial-coordinate-coupling.yaml).
#include <mbd/model_system.hpp>
#include <mbd/reactions.hpp>
#include <mbd/sdk/rotation.hpp>
#include <mbd/simulation.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "support/test_support.hpp"

namespace mbd {
namespace {

constexpr double T = 0.1, I_a = 0.02, I_b = 0.008, M = 0.4, ratio = -2.0, lead = 0.05;
constexpr double I_eff = I_a + ratio * ratio * I_b + lead * lead * M;

const char* kScene = R"(
dimension: spatial
gravity: [0, 0, -9.81]
bodies:
  - {name: wheel_a, mass: 1.0, inertia: [0.01, 0.01, 0.02], position: [0, 0, 0]}
  - {name: wheel_b, mass: 0.5, inertia: [0.004, 0.004, 0.008], position: [0.3, 0, 0]}
  - {name: slider, mass: 0.4, inertia: [0.001, 0.001, 0.001], position: [0, 0.5, 0.1]}
joints:
  - {name: axle_a, type: revolute, bodies: [ground, wheel_a], point: [0, 0, 0], axis: [0, 0, 1]}
  - {name: axle_b, type: revolute, bodies: [ground, wheel_b], point: [0.3, 0, 0], axis: [0, 0, 1]}
  - {name: rail, type: prismatic, bodies: [ground, slider], point: [0, 0.5, 0.1], axis: [1, 0, 0]}
  - name: gear
    type: coordinate_coupling
    bodies: [ground, wheel_b, wheel_a]
    follower: {bodies: [ground, wheel_b], point: [0.3, 0, 0], axis: [0, 0, 1]}
    leader: {bodies: [ground, wheel_a], point: [0, 0, 0], axis: [0, 0, 1]}
    multiplier: -2
  - name: rack
    type: coordinate_coupling
    bodies: [ground, slider, wheel_a]
    follower: {bodies: [ground, slider], point: [0, 0.5, 0.1], axis: [1, 0, 0], coordinate: travel}
    leader: {bodies: [ground, wheel_a], axis: [0, 0, 1], coordinate: angle}
    multiplier: 0.05
forces:
  - {name: motor, type: point_torque, body: wheel_a, torque: [0, 0, 0.1]}
)";

// The rotation angle about world z of body k (its Euler parameters, q = [R, p] per body).
double turn_about_z(const State& s, int k) {
    const Vec4 p = s.q.segment<4>(7 * k + 3).normalized();
    return 2.0 * std::atan2(p[3], p[0]);
}

const BodyReaction& on_body(const std::vector<JointReaction>& all, const std::string& joint, int body) {
    for (const JointReaction& r : all)
        if (r.name == joint)
            for (const BodyReaction& b : r.on)
                if (b.body == body) return b;
    throw std::runtime_error("no reaction of " + joint + " on body " + std::to_string(body));
}

TEST(CoordinateCoupling, GearAndRackCouplingsFollowTheClosedFormInEveryFormulation) {
    const Model model = test::scene(kScene, "coupled-wheels.yaml");
    ModelSystem system(model);
    const double qa_dd = T / I_eff;
    for (const std::string& formulation : test::shared_registry().type_names("formulation")) {
        SimulationSettings s = test::adaptive_run(formulation, "dop853", 1e-11, 1.0, 0.1);
        s.reactions = true;
        double worst_motion = 0.0, worst_load = 0.0;
        int checked = 0;
        simulate(model, test::shared_registry(), s, [&](const SimulationSample& sample) {
            const double t = sample.state.t, qa = 0.5 * qa_dd * t * t;
            worst_motion = std::max({worst_motion, std::abs(turn_about_z(sample.state, 0) - qa),
                                     std::abs(turn_about_z(sample.state, 1) - ratio * qa),
                                     std::abs(sample.state.q[14] - lead * qa)});
            if (t == 0.0 || !sample.lambda) return true;
            const std::vector<JointReaction> r = joint_reactions(system, sample.state, *sample.lambda);
            const double on_b = I_b * ratio * qa_dd, on_slider = M * lead * qa_dd;
            worst_load = std::max({worst_load, std::abs(on_body(r, "gear", 1).torque.z() - on_b),
                                   std::abs(on_body(r, "gear", 0).torque.z() + ratio * on_b),
                                   std::abs(on_body(r, "rack", 2).force.x() - on_slider),
                                   std::abs(on_body(r, "rack", 0).torque.z() + lead * on_slider)});
            ++checked;
            return true;
        });
        std::printf("%-12s motion %.2e rad or m  loads %.2e N m or N (wheel b's moment %.4g N m)\n",
                    formulation.c_str(), worst_motion, worst_load, I_b * ratio * qa_dd);
        EXPECT_EQ(checked, 10) << formulation;
        EXPECT_LT(worst_motion, 1e-8) << formulation;
        EXPECT_LT(worst_load, 1e-8) << formulation;
    }
}

// A side naming a body the coupling does not list is refused naming the joint and the body.
TEST(CoordinateCoupling, ABodyOutsideTheJointsListIsRefused) {
    const std::string yaml = test::replaced(kScene, "leader: {bodies: [ground, wheel_a], axis: [0, 0, 1], coordinate: angle}",
                                            "leader: {bodies: [ground, wheel_b], axis: [0, 0, 1], coordinate: angle}");
    try {
        test::scene(yaml);
        ADD_FAILURE() << "a leader on a body outside the rack's bodies loaded";
    } catch (const std::exception& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("joint 'rack'"), std::string::npos) << what;
        EXPECT_NE(what.find("body 'wheel_b' is not one of the joint's 'bodies'"), std::string::npos) << what;
    }
}

}  // namespace
}  // namespace mbd
