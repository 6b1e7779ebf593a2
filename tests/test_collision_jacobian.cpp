// The collision element's force Jacobians taken one contact at a time (sparse,
// core/src/evaluation/coupled_force_jacobians.cpp) against the whole element's differences (dense, the path
// every element without couplings takes) and against finite differences of the System's forces;
// and the workspace that made 10,000 bodies fail (58 GB) is gone.
#include "support/test_support.hpp"

#include <mbd/data.hpp>
#include <mbd/model_system.hpp>
#include <mbd/sdk/force_couplings.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>

namespace {

// Three spheres pressed into the ground and into one another, and a tilted box on a sphere and
// on the ground (several contacts a pair), all moving and spinning so that damping and friction
// load every contact.
const char* kPile = R"(
dimension: spatial
gravity: [0, 0, -9.81]
ground:
  collision:
    - {shape: plane, normal: [0, 0, 1], material: {static_friction: 0.5}}
bodies:
  - {name: a, mass: 0.1, inertia: [1e-4, 1.2e-4, 0.9e-4], position: [0, 0, 0.049], velocity: [0.1, -0.05, 0.02],
     angular_velocity: [1, 2, -0.5], collision: [{shape: sphere, radius: 0.05, material: &m {stiffness: 1e6,
     restitution: 0.5, impact_velocity: 1, static_friction: 0.5, kinetic_friction: 0.4, stiction_velocity: 0.01}}]}
  - {name: b, mass: 0.1, inertia: [1e-4, 1e-4, 1e-4], position: [0.098, 0.003, 0.0495], velocity: [-0.2, 0.1, -0.03],
     angular_velocity: [-1, 0.5, 2], collision: [{shape: sphere, radius: 0.05, material: *m}]}
  - {name: c, mass: 0.1, inertia: [1e-4, 1e-4, 1e-4], position: [0.05, 0.085, 0.0492], velocity: [0.05, 0.02, 0.01],
     angular_velocity: [0.3, -1, 0.2], collision: [{shape: sphere, radius: 0.05, material: *m}]}
  - {name: box, mass: 0.5, inertia: [2e-3, 3e-3, 4e-3], position: [0.3, 0, 0.058],
     orientation: {axis: [1, 0.5, 0], angle: 0.03}, velocity: [0.1, 0.2, -0.1], angular_velocity: [0.2, -0.4, 1],
     collision: [{shape: box, size: [0.3, 0.2, 0.12], material: *m}]}
  - {name: d, mass: 0.1, inertia: [1e-4, 1e-4, 1e-4], position: [0.32, 0.02, 0.167], velocity: [0, 0.1, -0.2],
     angular_velocity: [2, 0, 1], collision: [{shape: sphere, radius: 0.05, material: *m}]}
)";

// The collision element without its couplings: the core then differences it whole (dense).
class Whole final : public mbd::Force {
public:
    explicit Whole(std::shared_ptr<const mbd::Force> inner) : inner_(std::move(inner)) {}
    void evaluate(const mbd::BodyStates& b, Eigen::Ref<Eigen::VectorXd> Q) const override { inner_->evaluate(b, Q); }

private:
    std::shared_ptr<const mbd::Force> inner_;
};

mbd::ForceInstance& collision_element(mbd::Model& model) {
    for (mbd::ForceInstance& f : model.forces)
        if (f.type == "collision_contact") return f;
    throw std::runtime_error("no collision element");
}

double max_abs(const Eigen::MatrixXd& m) { return m.cwiseAbs().maxCoeff(); }

// Both paths' Jacobians of a scene: the contact-by-contact (sparse) and the whole element's (dense).
struct BothPaths {
    Eigen::MatrixXd Sq, Sv, Dq, Dv;
};

BothPaths both_paths(const std::string& yaml) {
    mbd::Model sparse_model = mbd::test::scene(yaml);
    mbd::Model dense_model = sparse_model;
    mbd::ForceInstance& dense = collision_element(dense_model);
    dense.force = std::make_shared<Whole>(dense.force);
    EXPECT_NE(dynamic_cast<const mbd::ForceCouplings*>(collision_element(sparse_model).force.get()), nullptr);
    mbd::ModelSystem sparse_system(sparse_model), dense_system(dense_model);
    const mbd::State state = sparse_system.initial_state();
    Eigen::SparseMatrix<double> sq, sv, dq, dv;
    sparse_system.force_jacobians(state, sq, sv);
    dense_system.force_jacobians(state, dq, dv);
    return {Eigen::MatrixXd(sq), Eigen::MatrixXd(sv), Eigen::MatrixXd(dq), Eigen::MatrixXd(dv)};
}

// Where each body has one partner (two spheres pressed together in the air, a sphere on the
// ground, a box on the ground on its four corners, all moving), each row of Q is one pair's force in both
// paths, computed from the same perturbed states: the two agree to 1e-12 (exactly, in practice).
TEST(CollisionJacobian, ContactByContactEqualsTheWholeElementsDifferences) {
    std::string yaml = mbd::test::replaced(kPile, "position: [0, 0, 0.049]", "position: [0, 0, 0.5]");
    yaml = mbd::test::replaced(yaml, "position: [0.098, 0.003, 0.0495]", "position: [0.098, 0.003, 0.5]");
    yaml = mbd::test::replaced(yaml, "position: [0.32, 0.02, 0.167]", "position: [0.32, 0.02, 0.3]");
    const BothPaths p = both_paths(yaml);
    EXPECT_GT(max_abs(p.Dq.block(0, 6, 6, 6)), 1e3);     // a-b couple
    EXPECT_GT(max_abs(p.Dq.block(12, 12, 6, 6)), 1e3);   // c on the ground
    EXPECT_GT(max_abs(p.Dq.block(18, 18, 6, 6)), 1e3);   // the box on the ground
    EXPECT_EQ(max_abs(p.Dq.block(24, 24, 6, 6)), 0.0);   // d is in the air
    EXPECT_LE(max_abs(p.Sq - p.Dq), 1e-12 * max_abs(p.Dq));
    EXPECT_LE(max_abs(p.Sv - p.Dv), 1e-12 * max_abs(p.Dv));
}

// Where bodies touch several others, the whole element's differences subtract sums of several
// pairs' forces, summed in the broad phase's order: they carry its rounding, eps |Q| / h, about
// 1e-9 of the largest entry (5e-10 in the block of two bodies that never touch, where the
// contact-by-contact Jacobian has an exact zero). The paths agree to that.
TEST(CollisionJacobian, ContactByContactAgreesWithTheWholeElementToItsRoundingInAPile) {
    const BothPaths p = both_paths(kPile);
    for (int b = 0; b < 5; ++b) EXPECT_GT(max_abs(p.Dq.block(6 * b, 6 * b, 6, 6)), 1e3) << b;  // all loaded
    EXPECT_GT(max_abs(p.Dq.block(0, 6, 6, 6)), 1e3);    // a-b couple
    EXPECT_GT(max_abs(p.Dq.block(18, 24, 6, 6)), 1e3);  // box-d couple
    EXPECT_EQ(max_abs(p.Sq.block(0, 18, 6, 6)), 0.0);   // a and the box do not touch
    EXPECT_LT(max_abs(p.Dq.block(0, 18, 6, 6)), 1e-8);  // the dense path's rounding there
    EXPECT_LT(max_abs(p.Sq - p.Dq), 1e-9 * max_abs(p.Dq));
    EXPECT_LT(max_abs(p.Sv - p.Dv), 1e-9 * max_abs(p.Dv));
}

// dQ/dq and dQ/dv against central differences of the System's generalized forces (gravity and
// the gyroscopic term included) along a random direction of the positions and of the velocities.
TEST(CollisionJacobian, SparseJacobiansMatchDifferencesOfTheGeneralizedForces) {
    const mbd::Model model = mbd::test::scene(kPile);
    mbd::ModelSystem system(model);
    const mbd::State state = system.initial_state();
    Eigen::SparseMatrix<double> Kq, Kv;
    system.force_jacobians(state, Kq, Kv);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> unit(-1, 1);
    Eigen::VectorXd direction(model.nv());
    for (int k = 0; k < model.nv(); ++k) direction[k] = unit(rng);
    const double h = 1e-6;
    auto Q_at = [&](double step, bool velocity) {
        mbd::State s = state;
        if (velocity) s.v += step * direction;
        else system.advance_positions(s.q, step * direction);
        Eigen::VectorXd Q;
        system.generalized_forces(s, Q);
        return Q;
    };
    for (bool velocity : {false, true}) {
        const Eigen::VectorXd fd = (Q_at(h, velocity) - Q_at(-h, velocity)) / (2 * h);
        const Eigen::VectorXd exact = (velocity ? Kv : Kq) * direction;
        EXPECT_LT((fd - exact).cwiseAbs().maxCoeff(), 1e-6 * fd.cwiseAbs().maxCoeff()) << "velocity " << velocity;
    }
}

// A collision element over 500 spheres: Data holds no workspace square in its velocities
// (it would be 3,000 x 3,000 here, 58 GB at 10,000 bodies), and the Jacobian has the spheres'
// own blocks only: each sphere 1 mm into the ground, at rest, has the one entry
// dF_z/dz = -1.5 k delta^0.5 of its Hunt-Crossley law.
TEST(CollisionJacobian, TheWorkspaceAndTheJacobianGrowWithBodiesAndContacts) {
    std::ostringstream s;
    s << "dimension: spatial\nground:\n  collision: [{shape: plane, normal: [0, 0, 1]}]\nbodies:\n";
    const int count = 500;
    const double k = 1e6, delta = 1e-3;
    for (int b = 0; b < count; ++b)  // a row of spheres 1 mm into the ground, apart
        s << "  - {name: s" << b << ", mass: 0.1, inertia: [1e-4, 1e-4, 1e-4], position: [" << 0.12 * b
          << ", 0, 0.049], collision: [{shape: sphere, radius: 0.05, material: {stiffness: " << k
          << ", static_friction: 0.5, stiction_velocity: 0.01}}]}\n";
    const mbd::Model model = mbd::test::scene(s.str());
    mbd::ModelSystem system(model);
    EXPECT_LE(system.data().force_dQ_dq.size(), 36);
    EXPECT_LE(system.data().force_dQ_dv.size(), 36);
    Eigen::SparseMatrix<double> Kq, Kv;
    system.force_jacobians(system.initial_state(), Kq, Kv);
    EXPECT_EQ(Kq.nonZeros(), count);
    const double slope = -1.5 * k * std::sqrt(delta);
    for (int b = 0; b < count; ++b) ASSERT_NEAR(Kq.coeff(6 * b + 2, 6 * b + 2), slope, 1e-6 * std::abs(slope)) << b;
}

}  // namespace
