// The index-3 problem a formulation provides (kit index3_problem.hpp) and generalized_alpha
// working through it:
// - augmented provides one; every other standard formulation says it has none, and a run of
//   generalized_alpha with it is refused naming the formulation, before any work;
// - the augmented problem's residual vanishes at the augmented formulation's own accelerations
//   and multipliers (its Schur-complement solve, another route to the same equations);
// - its iteration matrix is the derivative of the residuals (r, C / beta') along the method's
//   update q = q0 (+) beta' vdot, v = v0 + gamma' vdot: central differences, with a spring,
//   a damper and a joint whose Jacobian turns with the body (the geometric stiffness);
// - generalized_alpha through the augmented formulation follows the pendulum's 1-DOF equation
//   (a reference integrated on its own) at second order, holding the joint.
#include "support/function_problem.hpp"
#include "support/convergence_order.hpp"
#include "support/test_support.hpp"

#include <mbd/formulation_setup.hpp>
#include <mbd/integrator.hpp>
#include <mbd/kit/formulation.hpp>
#include <mbd/kit/index3_problem.hpp>
#include <mbd/model_system.hpp>
#include <mbd/simulation.hpp>

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace {

using Eigen::VectorXd;

const char* const kFormulations[] = {"augmented", "embedding", "amalgamated", "hamiltonian"};

// A spherical pendulum whose bob also hangs on a spring-damper from a point beside the pivot:
// dQ/dq (spring), dQ/dv (damper), and J that turns with the bob (geometric stiffness).
const char* const kSpringPendulum = R"(
name: spring-pendulum
dimension: spatial
gravity: [0, 0, -9.81]
bodies:
  - name: bob
    mass: 1.5
    inertia: [0.02, 0.03, 0.04]
    position: [0.3, 0.1, -0.4]
    velocity: [0.2, 0.3, 0.1]
    angular_velocity: [0.5, -1, 2]
joints:
  - {name: ball, type: spherical, bodies: [ground, bob], point: [0, 0, 0]}
forces:
  - name: spring
    type: spring_damper
    bodies: [ground, bob]
    points: [[0.5, 0, 0], [0.35, 0.1, -0.4]]
    stiffness: 80
    damping: 3
    rest_length: 0.3
)";

TEST(Index3Problem, AugmentedProvidesOneAndTheOtherFormulationsHaveNone) {
    for (const char* name : kFormulations) {
        mbd::Param node;
        const std::shared_ptr<mbd::Formulation> f = mbd::test::make_formulation(name, node);
        EXPECT_EQ(f->index3_problem() != nullptr, std::string(name) == "augmented") << name;
    }
}

TEST(Index3Problem, GeneralizedAlphaRefusesAFormulationWithoutOneNamingIt) {
    const mbd::Model model = mbd::test::load("examples/planar-revolute.yaml");
    for (const char* name : kFormulations) {
        if (std::string(name) == "augmented") continue;
        mbd::SimulationSettings s;
        s.formulation = name;
        s.integrator = "generalized_alpha";
        s.integration.step = 1e-3;
        s.t_end = 0.1;
        s.progress = false;
        s.messages = mbd::MessageLog::silent();
        long samples = 0;
        try {
            mbd::simulate(model, mbd::test::shared_registry(), s, [&](const mbd::SimulationSample&) {
                ++samples;
                return true;
            });
            ADD_FAILURE() << name << ": no InputError";
        } catch (const mbd::InputError& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find("generalized_alpha needs the formulation's index-3 problem"), std::string::npos) << what;
            EXPECT_NE(what.find("formulation '" + std::string(name) + "' does not provide"), std::string::npos) << what;
            EXPECT_NE(what.find("--formulation augmented"), std::string::npos) << what;
        }
        EXPECT_EQ(samples, 0) << name << ": refused before any step";
    }
}

struct Bound {
    mbd::Model model;
    std::unique_ptr<mbd::ModelSystem> system;
    std::shared_ptr<mbd::Formulation> formulation;
    mbd::Param node;
    mbd::State state;  // assembled, consistent velocities
};

std::unique_ptr<Bound> bind_augmented(const std::string& yaml) {
    auto b = std::make_unique<Bound>();
    b->model = mbd::test::scene(yaml);
    b->system = std::make_unique<mbd::ModelSystem>(b->model);
    b->formulation = mbd::test::make_formulation("augmented", b->node);
    b->formulation->bind(*b->system, {});
    b->state = b->system->initial_state();
    b->state.t = 0.0;
    b->system->assemble(b->state);
    b->system->consistent_velocities(b->state);
    return b;
}

TEST(Index3Problem, ResidualVanishesAtTheAugmentedFormulationsAccelerations) {
    auto b = bind_augmented(kSpringPendulum);
    mbd::Index3Problem& dae = *b->formulation->index3_problem();
    ASSERT_EQ(dae.velocity_count(), 6);
    ASSERT_EQ(dae.constraint_count(), 3);
    VectorXd vdot, lambda, r;
    b->formulation->accelerations(b->state, vdot);
    b->formulation->multipliers(b->state, lambda);
    dae.evaluate(b->state);
    dae.residual(vdot, lambda, r);
    const mbd::ConstraintValues& cv = dae.constraint_values();
    std::printf("residual at the augmented accelerations: |r| %.2e, |J vdot - gamma| %.2e, |C| %.2e, |lambda| %.3g\n",
                r.lpNorm<Eigen::Infinity>(), (cv.J * vdot - cv.gamma).lpNorm<Eigen::Infinity>(),
                cv.C.lpNorm<Eigen::Infinity>(), lambda.lpNorm<Eigen::Infinity>());
    EXPECT_GT(lambda.lpNorm<Eigen::Infinity>(), 1.0);  // the pivot carries the bob
    EXPECT_LT(r.lpNorm<Eigen::Infinity>(), 1e-10);
    EXPECT_LT((cv.J * vdot - cv.gamma).lpNorm<Eigen::Infinity>(), 1e-10);
    EXPECT_LT(cv.C.lpNorm<Eigen::Infinity>(), 1e-10);
    // a wrong multiplier shows in r
    dae.residual(vdot, lambda * 1.01, r);
    EXPECT_GT(r.lpNorm<Eigen::Infinity>(), 1e-3);
}

TEST(Index3Problem, IterationMatrixIsTheDerivativeOfTheScaledResiduals) {
    auto b = bind_augmented(kSpringPendulum);
    mbd::Index3Problem& dae = *b->formulation->index3_problem();
    const int nv = dae.velocity_count(), nc = dae.constraint_count(), n = nv + nc;
    const double beta_p = 3e-3, gamma_p = 6e-2;
    VectorXd x0, lambda0;
    b->formulation->accelerations(b->state, x0);
    b->formulation->multipliers(b->state, lambda0);
    // the method's update from (q0, v0) as the iterate vdot = x moves
    auto state_at = [&](const VectorXd& x) {
        mbd::State s = b->state;
        dae.advance_positions(s.q, beta_p * (x - x0));
        s.v = b->state.v + gamma_p * (x - x0);
        return s;
    };
    auto residuals = [&](const VectorXd& z) {
        const VectorXd x = z.head(nv), lambda = z.tail(nc);
        const mbd::State s = state_at(x);
        dae.evaluate(s);
        VectorXd r, out(n);
        dae.residual(x, lambda, r);
        out << r, dae.constraint_values().C / beta_p;
        return out;
    };
    VectorXd z0(n);
    z0 << x0, lambda0;
    for (const bool geometric : {true, false}) {
        const mbd::State s0 = state_at(x0);
        dae.evaluate(s0);
        mbd::Index3Problem::Triplets triplets;
        dae.iteration_matrix(beta_p, gamma_p, geometric ? &lambda0 : nullptr, triplets);
        Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n);
        for (const auto& t : triplets) A(t.row(), t.col()) += t.value();
        Eigen::MatrixXd D(n, n);
        const double delta = 1e-4;
        for (int j = 0; j < n; ++j) {
            VectorXd zp = z0, zm = z0;
            zp[j] += delta;
            zm[j] -= delta;
            D.col(j) = (residuals(zp) - residuals(zm)) / (2 * delta);
        }
        const double error = (A - D).lpNorm<Eigen::Infinity>(), scale = D.lpNorm<Eigen::Infinity>();
        // the geometric stiffness's size in the matrix: the part a missing or wrong-signed term leaves
        Eigen::MatrixXd without = D;
        if (geometric) {
            triplets.clear();
            dae.evaluate(s0);
            dae.iteration_matrix(beta_p, gamma_p, nullptr, triplets);
            without.setZero();
            for (const auto& t : triplets) without(t.row(), t.col()) += t.value();
        }
        std::printf("iteration matrix (geometric %d) vs central differences: max error %.2e of %.3g; geometric term "
                    "%.2e\n",
                    geometric, error, scale, (A - without).lpNorm<Eigen::Infinity>());
        if (geometric) {
            EXPECT_GT((A - without).lpNorm<Eigen::Infinity>(), 1e3 * 1e-7 * scale);  // the test sees the term
            EXPECT_LT(error, 1e-7 * scale);
        } else {
            // without it the matrix differs from the derivative by exactly that term
            EXPECT_GT(error, 1e-5 * scale);
            EXPECT_LT((A.topRightCorner(nv, nc) - D.topRightCorner(nv, nc)).lpNorm<Eigen::Infinity>(), 1e-7 * scale);
            EXPECT_LT((A.bottomRows(nc) - D.bottomRows(nc)).lpNorm<Eigen::Infinity>(), 1e-7 * scale);
        }
    }
}

TEST(Index3Problem, ProjectionAfterAStepGivesUnitEulerParameters) {
    auto b = bind_augmented(kSpringPendulum);
    mbd::Index3Problem& dae = *b->formulation->index3_problem();
    VectorXd q = b->state.q;
    q.tail(4) *= 1.001;  // the bob's Euler parameters, off the unit sphere
    dae.project_positions(q);
    EXPECT_NEAR(q.tail(4).norm(), 1.0, 1e-15);
    EXPECT_NEAR((q.tail(4) - b->state.q.tail(4)).norm(), 0.0, 1e-15);
    EXPECT_EQ(q.head(3), b->state.q.head(3));
}

// scenes/examples/planar-revolute.yaml: a 1 m slender link (m = 1, J = 1/12) pinned at one end,
// released 30 degrees from the vertical: J_O phi'' = -m g c sin(phi), J_O = 1/3, c = 1/2.
TEST(Index3Problem, GeneralizedAlphaThroughTheAugmentedFormulationFollowsThePendulum) {
    const mbd::Model model = mbd::test::load("examples/planar-revolute.yaml");
    const double pi = std::acos(-1.0), w2 = 9.81 * 0.5 / (1.0 / 3.0), T = 1.0;
    mbd::test::FunctionProblem one_dof(2, [&](double, const VectorXd& y, VectorXd& f) {
        f[0] = y[1];
        f[1] = -w2 * std::sin(y[0]);
    });
    std::vector<double> times;
    for (int k = 1; k <= 20; ++k) times.push_back(T * k / 20);
    mbd::IntegratorSettings reference_settings;
    reference_settings.tolerance = 1e-13;
    VectorXd z(2);
    z << pi / 6, 0.0;
    const mbd::test::RunResult reference = mbd::test::run("dopri5", reference_settings, one_dof, 0.0, z, times);
    ASSERT_EQ(reference.y.size(), times.size());

    std::vector<double> errors;
    for (double h : {0.01, 0.005, 0.0025}) {
        mbd::SimulationSettings s;
        s.formulation = "augmented";
        s.integrator = "generalized_alpha";
        s.integration.step = h;
        s.integration.rho_infinity = 0.8;
        s.t_end = T;
        s.output_step = T / 20;
        s.progress = false;
        double error = 0.0, joint = 0.0;
        size_t k = 0;
        mbd::simulate(model, mbd::test::shared_registry(), s, [&](const mbd::SimulationSample& sample) {
            if (sample.state.t == 0.0) return true;
            const VectorXd& q = sample.state.q;
            error = std::max(error, std::abs(q[2] + pi / 2 - reference.y.at(k++)[0]));
            // the pin, written here: the link's point 0.5 behind its centre stays at the origin
            joint = std::max({joint, std::abs(q[0] - 0.5 * std::cos(q[2])), std::abs(q[1] - 0.5 * std::sin(q[2]))});
            return true;
        });
        EXPECT_EQ(k, times.size());
        std::printf("augmented + generalized_alpha h = %.4f: max angle error %.3e, max pin gap %.2e\n", h, error, joint);
        EXPECT_LT(joint, 1e-9);
        errors.push_back(error);
    }
    mbd::test::expect_order_under_halving(errors, 1.7, 2.3, "augmented + generalized_alpha pendulum");
}

}  // namespace
