// The System the core hands to analysis plugins: mass matrix, generalized
// forces with the gyroscopic term, their Jacobians (analytic, and numerical
// for elements without them), and the energies, against independent sums.
#include "support/test_support.hpp"

#include <mbd/data.hpp>
#include <mbd/derivative_check.hpp>
#include <mbd/model_system.hpp>

#include <gtest/gtest.h>

#include <random>
#include <string>

namespace mbd {
namespace {

const char* kSpatialScene = R"(
name: two bodies on springs
dimension: spatial
gravity: [0, -9.81, 0]
bodies:
  - {name: a, mass: 2, inertia: [[0.3, 0.01, 0.02], [0.01, 0.4, 0.03], [0.02, 0.03, 0.5]], position: [0, 0, 0]}
  - {name: b, mass: 3, inertia: [0.2, 0.5, 0.7], position: [1, 0.2, -0.1],
     orientation: {axis: [1, 2, 3], angle: 0.7}, angular_velocity: [1, -2, 3]}
joints:
  - {name: ball, type: spherical, bodies: [ground, a], point: [0, 0.5, 0]}
forces:
  - {type: spring_damper, bodies: [a, b], points: [[0.1, 0, 0], [0, 0.1, 0]], stiffness: 300, damping: 4, rest_length: 0.8}
  - {type: bushing, bodies: [ground, b], stiffness: [10, 20, 30, 1, 2, 3], damping: [1, 1, 1, 0.1, 0.1, 0.1]}
  - {type: quadratic_drag, bodies: [a, b], coefficient: 0.7}
)";

struct Fixture {
    Registry registry{{test::build_plugin_dir(), std::filesystem::path(MBD_TEST_PLUGIN_DIR)}};
    Model model = load_scene_text(kSpatialScene, "springs.yaml", registry);
    ModelSystem system{model};
};

State random_state(const Model& model, std::mt19937& rng) { return mbd::random_state(model, rng, 0.5, 2.0, 0.3); }

TEST(ModelSystem, MassMatrixIsBlockDiagonalOfMassesAndBodyInertias) {
    Fixture f;
    const Eigen::MatrixXd M(f.system.mass_matrix());
    ASSERT_EQ(M.rows(), 12);
    Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(12, 12);
    expected.block<3, 3>(0, 0) = 2 * Mat3::Identity();
    expected.block<3, 3>(3, 3) << 0.3, 0.01, 0.02, 0.01, 0.4, 0.03, 0.02, 0.03, 0.5;
    expected.block<3, 3>(6, 6) = 3 * Mat3::Identity();
    expected.block<3, 3>(9, 9) = Vec3(0.2, 0.5, 0.7).asDiagonal();
    EXPECT_LT((M - expected).norm(), 1e-15);
}

TEST(ModelSystem, KineticEnergyIsTranslationalPlusRotational) {
    Fixture f;
    std::mt19937 rng(7);
    const State s = random_state(f.model, rng);
    double T = 0;
    for (int k = 0; k < 2; ++k) {
        const Vec3 v = s.v.segment<3>(6 * k), w = s.v.segment<3>(6 * k + 3);
        T += 0.5 * f.model.bodies[k].mass * v.squaredNorm() + 0.5 * w.dot(f.model.bodies[k].inertia * w);
    }
    EXPECT_NEAR(f.system.kinetic_energy(s), T, 1e-12 * T);
}

TEST(ModelSystem, GyroscopicMomentIsIncluded) {
    // with the forces' contributions removed, the rotational rows hold -w x (J w)
    Fixture f;
    std::mt19937 rng(11);
    const State s = random_state(f.model, rng);
    Eigen::VectorXd Q;
    f.system.generalized_forces(s, Q);
    Eigen::VectorXd forces_only = Eigen::VectorXd::Zero(12);
    BodyPoses poses(f.model);
    poses.update(s);
    for (const ForceInstance& fi : f.model.forces) {
        Eigen::VectorXd local = Eigen::VectorXd::Zero(6 * fi.bodies.size());
        fi.force->evaluate(poses.view(fi.bodies, s.t), local);
        for (size_t b = 0; b < fi.bodies.size(); ++b)
            if (fi.bodies[b] != kGround) forces_only.segment<6>(6 * fi.bodies[b]) += local.segment<6>(6 * b);
    }
    for (int k = 0; k < 2; ++k) {
        const Vec3 w = s.v.segment<3>(6 * k + 3);
        const Vec3 gyro = -w.cross(f.model.bodies[k].inertia * w);
        EXPECT_LT((Q.segment<3>(6 * k + 3) - forces_only.segment<3>(6 * k + 3) - gyro).norm(), 1e-12);
    }
}

TEST(ModelSystem, ForceJacobiansMatchFiniteDifferencesIncludingElementsWithoutJacobians) {
    Fixture f;
    EXPECT_FALSE(f.model.forces.back().force->has_jacobians());  // the drag goes through the numerical path
    std::mt19937 rng(3);
    for (int trial = 0; trial < 3; ++trial) {
        const State s = random_state(f.model, rng);
        Eigen::SparseMatrix<double> Kq, Kv;
        f.system.force_jacobians(s, Kq, Kv);
        Eigen::MatrixXd Kq_fd(12, 12), Kv_fd(12, 12);
        const double h = 1e-6;
        for (int c = 0; c < 12; ++c) {
            Eigen::VectorXd dv = Eigen::VectorXd::Zero(12);
            dv[c] = h;
            Eigen::VectorXd Qp, Qm;
            State sp = s, sm = s;
            advance_positions(f.model, sp.q, dv);
            advance_positions(f.model, sm.q, -dv);
            f.system.generalized_forces(sp, Qp);
            f.system.generalized_forces(sm, Qm);
            Kq_fd.col(c) = (Qp - Qm) / (2 * h);
            sp = s;
            sm = s;
            sp.v[c] += h;
            sm.v[c] -= h;
            f.system.generalized_forces(sp, Qp);
            f.system.generalized_forces(sm, Qm);
            Kv_fd.col(c) = (Qp - Qm) / (2 * h);
        }
        EXPECT_LT((Eigen::MatrixXd(Kq) - Kq_fd).norm() / Kq_fd.norm(), 1e-6);
        EXPECT_LT((Eigen::MatrixXd(Kv) - Kv_fd).norm() / Kv_fd.norm(), 1e-6);
    }
}

TEST(ModelSystem, PotentialEnergyOfGravityIsMinusMassTimesGravityDotPosition) {
    const char* scene = R"(
dimension: spatial
gravity: [0, -9.81, 0]
bodies:
  - {name: a, mass: 2, inertia: [1, 1, 1], position: [0.5, 1.5, 0]}
  - {name: b, mass: 3, inertia: [1, 1, 1], position: [0, -2, 4]}
)";
    Registry registry({test::build_plugin_dir()});
    Model model = load_scene_text(scene, "fall.yaml", registry);
    ModelSystem system(model);
    EXPECT_NEAR(system.potential_energy(model.initial_state()), 2 * 9.81 * 1.5 + 3 * 9.81 * -2, 1e-12);
    EXPECT_TRUE(system.conservative());
}

// Gravity is one element over every body whose load is constant: the square Jacobian
// workspace of Data is sized by the widest other element (two bodies, 12 x 12 spatial), not
// by N (a 2,000-link chain would otherwise hold two 12,000 x 12,000 matrices, 2.3 GB), and
// gravity's zero Jacobians are not evaluated.
TEST(ModelSystem, DataWorkspaceIsLinearInTheBodiesWithGravityOverAll) {
    const int n = 2000;
    std::string scene = "dimension: spatial\ngravity: [0, 0, -9.81]\nbodies:\n";
    for (int k = 0; k < n; ++k)
        scene += "  - {name: l" + std::to_string(k) + ", mass: 1, inertia: [1e-4, 1e-3, 1e-3], position: [" +
                 std::to_string(0.1 * k + 0.05) + ", 0, 0]}\n";
    scene += "joints:\n";
    for (int k = 0; k < n; ++k)
        scene += "  - {name: j" + std::to_string(k) + ", type: spherical, bodies: [" +
                 (k == 0 ? std::string("ground") : "l" + std::to_string(k - 1)) + ", l" + std::to_string(k) +
                 "], point: [" + std::to_string(0.1 * k) + ", 0, 0]}\n";
    scene += "forces:\n  - {type: spring_damper, bodies: [l0, l1], stiffness: 10, damping: 1}\n";
    Model model = test::scene(scene, "long-chain.yaml");
    const Data data(model);
    EXPECT_EQ(data.force_dQ_dq.rows(), 12);
    EXPECT_EQ(data.force_dQ_dv.cols(), 12);
    ModelSystem system(model);
    Eigen::SparseMatrix<double> Kq, Kv;
    const State s = model.initial_state();
    system.force_jacobians(s, Kq, Kv);
    EXPECT_EQ(Kq.rows(), 6 * n);
    // the spring at rest between l0 and l1 is the only stiffness: its 12 x 12 block at most
    EXPECT_LE(Kq.nonZeros(), 144);
    Eigen::VectorXd Q;
    system.generalized_forces(s, Q);
    EXPECT_NEAR(Q[6 * (n - 1) + 2], -9.81, 1e-12);  // m g on the last link, along -z
}

TEST(ModelSystem, RowDescriptionsNameJointsAndDrivers) {
    Fixture f;
    EXPECT_EQ(f.system.joint_rows(), 3);
    EXPECT_EQ(f.system.describe_row(0), "joint 'ball' (x)");
    EXPECT_EQ(f.system.joint(0).first_row, 0);
    EXPECT_EQ(f.system.joint(0).rows, 3);
}

// constraint_gamma is constraints()'s gamma, row for row, on mechanisms of both dimensions
// with drivers (the slider crank's, the Bricard's redundant rows, the car axis's driven loop),
// at random states off the constraint manifold.
TEST(ModelSystem, GammaAloneEqualsTheFullEvaluationsGamma) {
    std::mt19937 rng(7);
    for (const char* scene : {"dynamics/slider-crank.yaml", "bench/a04-bricard.yaml", "bench/car-axis.yaml",
                              "bench/a05-flyball.yaml", "dynamics/heavy-top.yaml"}) {
        SCOPED_TRACE(scene);
        const Model model = test::load(scene);
        ModelSystem system{model};
        for (int trial = 0; trial < 3; ++trial) {
            State state = random_state(model, rng);
            state.t = 0.3 * trial;
            for (bool drivers : {true, false}) {
                ConstraintValues cv;
                system.constraints(state, cv, drivers);
                Eigen::VectorXd gamma;
                system.constraint_gamma(state, gamma, drivers);
                ASSERT_EQ(gamma.size(), cv.gamma.size());
                EXPECT_EQ((gamma - cv.gamma).lpNorm<Eigen::Infinity>(), 0.0);
            }
        }
    }
}

// A joint that says its gamma does not depend on the translational velocities
// (Joint::gamma_depends_on_translation: the Hamiltonian's polarization then skips them) keeps
// its rows' gamma, and its driver's, bit for bit when every body's translational velocity
// changes; on the scenes below the pins and ball joints say so, the prismatic joints do not.
TEST(ModelSystem, TranslationFreeJointsKeepGammaWhenTheTranslationalVelocitiesChange) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> change(-3.0, 3.0);
    int translation_free = 0, dependent = 0;
    for (const char* scene : {"bench/chain-5.yaml", "bench/car-axis.yaml", "bench/a04-bricard.yaml",
                              "bench/a05-flyball.yaml", "dynamics/heavy-top.yaml", "dynamics/slider-crank.yaml",
                              "extreme/spatial-chain-50.yaml"}) {
        SCOPED_TRACE(scene);
        const Model model = test::load(scene);
        ModelSystem system{model};
        const int translational = model.dimension == Dimension::Planar ? 2 : 3;
        for (int trial = 0; trial < 3; ++trial) {
            State state = random_state(model, rng);
            Eigen::VectorXd before, after;
            system.constraint_gamma(state, before, true);
            for (int b = 0; b < system.body_count(); ++b)
                for (int c = 0; c < translational; ++c) state.v[model.v_offset(b) + c] += change(rng);
            system.constraint_gamma(state, after, true);
            for (int j = 0; j < system.joint_count(); ++j) {
                const JointInfo& info = system.joint(j);
                if (info.joint->gamma_depends_on_translation()) {
                    dependent += trial == 0;
                    continue;
                }
                translation_free += trial == 0;
                for (int r = info.first_row; r < info.first_row + info.rows; ++r)
                    EXPECT_EQ(after[r], before[r]) << "joint '" << info.name << "' row " << r;
                for (int d = 0; d < system.driver_count(); ++d)
                    if (system.driver(d).joint == j)
                        EXPECT_EQ(after[system.driver(d).row], before[system.driver(d).row]) << "driver " << d;
            }
        }
    }
    EXPECT_GE(translation_free, 50);  // the chains' pins and ball joints, the Bricard's revolutes
    EXPECT_GE(dependent, 2);          // the slider crank's and the flyball's sliders
}

}  // namespace
}  // namespace mbd
