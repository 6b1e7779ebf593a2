// DOP853 (core/src/integrators/dop853.cpp, coefficients in dop853_tableau.hpp) against
// independent oracles:
//  - the Runge-Kutta order conditions, sum_i b_i Phi_i(t) = 1 / gamma(t) over every rooted
//    tree t (Butcher; Hairer, Norsett & Wanner, Solving ODE I, Sec. II.2), enumerated here:
//    the method through order 8 (and not 9), the 5th- and 3rd-order error estimators, and
//    the continuous extension through order 7 (sum_i b_i(s) Phi_i(t) = s^|t| / gamma(t));
//    the row sums c_i = sum_j a_ij;
//  - the measured order on IFToMM A01 (the closed-form pendulum) from the error against
//    the work over a range of tolerances, on outputs that are mostly interpolated;
//  - the heavy top's steady precession (book Sec. 8.1, closed form), the smooth ODE
//    y' = -y + sin t (closed form) and the projected rotation on the unit circle.
// Event location and the allocation-free steps are tested with dopri5's tests
// (tests/test_joint_stop.cpp, tests/test_allocations.cpp), run for dop853 as well.
#include "support/function_problem.hpp"
#include "support/convergence_order.hpp"
#include "support/test_support.hpp"

#include "dop853_tableau.hpp"

#include <mbd/integrator.hpp>
#include <mbd/sdk/rotation.hpp>
#include <mbd/simulation.hpp>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

namespace {

namespace tableau = mbd::integrators::dop853;
constexpr int kS = tableau::kDenseStages;
using Weights = std::array<double, kS>;

// ------------------------------------------------------------------ rooted trees
// A rooted tree as the list of its root's subtrees (indices into the list of all trees,
// non-decreasing: one canonical form per tree), its order |t| and density gamma(t).
struct Tree {
    std::vector<int> children;
    int order = 1;
    double gamma = 1.0;
};

// Every rooted tree through max_order, by order (1, 1, 2, 4, 9, 20, 48, 115, 286 of each).
std::vector<Tree> rooted_trees(int max_order) {
    std::vector<Tree> trees{Tree{}};
    for (int n = 2; n <= max_order; ++n) {
        const size_t known = trees.size();  // trees of order < n
        // every non-decreasing list of subtrees whose orders add up to n - 1
        std::function<void(int, size_t, std::vector<int>&)> extend = [&](int left, size_t from, std::vector<int>& list) {
            if (left == 0) {
                Tree t{list, n, static_cast<double>(n)};
                for (int c : list) t.gamma *= trees[c].gamma;
                trees.push_back(t);
                return;
            }
            for (size_t c = from; c < known; ++c)
                if (trees[c].order <= left) {
                    list.push_back(static_cast<int>(c));
                    extend(left - trees[c].order, c, list);
                    list.pop_back();
                }
        };
        std::vector<int> list;
        extend(n - 1, 0, list);
    }
    return trees;
}

// Phi_i(t) for every tree: 1 for the single node, prod over the subtrees u of (A Phi(u))_i.
std::vector<Weights> elementary_weights(const std::vector<Tree>& trees) {
    std::vector<Weights> phi(trees.size());
    for (size_t k = 0; k < trees.size(); ++k) {
        phi[k].fill(1.0);
        for (int c : trees[k].children)
            for (int i = 0; i < kS; ++i) {
                double sum = 0.0;
                for (int j = 0; j < i; ++j) sum += tableau::a[i][j] * phi[c][j];
                phi[k][i] *= sum;
            }
    }
    return phi;
}

double dot(const Weights& w, const Weights& phi) {
    double s = 0.0;
    for (int i = 0; i < kS; ++i) s += w[i] * phi[i];
    return s;
}

// The worst residual |w . Phi(t) - target(t)| over the trees of one order.
template <class Target>
double worst_residual(const std::vector<Tree>& trees, const std::vector<Weights>& phi, const Weights& w, int order,
                      Target&& target) {
    double worst = 0.0;
    for (size_t k = 0; k < trees.size(); ++k)
        if (trees[k].order == order) worst = std::max(worst, std::abs(dot(w, phi[k]) - target(trees[k])));
    return worst;
}

Weights weights_b() {
    Weights b{};
    for (int i = 0; i < tableau::kStages; ++i) b[i] = tableau::a[12][i];
    return b;
}

// The weights b_i(s) of the continuous extension u(s) = y + h sum_i b_i(s) k_i, from the
// nested form of dop853_tableau.hpp with r1 = h b.k, r2 = h k0 - r1, r3 = r1 - h k12 - r2.
Weights dense_weights(double s) {
    const Weights b = weights_b();
    const double s1 = 1.0 - s;
    Weights w{};
    for (int i = 0; i < kS; ++i) {
        const double r1 = b[i], r2 = (i == 0 ? 1.0 : 0.0) - r1, r3 = r1 - (i == 12 ? 1.0 : 0.0) - r2;
        const double r4 = tableau::d[0][i], r5 = tableau::d[1][i], r6 = tableau::d[2][i], r7 = tableau::d[3][i];
        w[i] = s * (r1 + s1 * (r2 + s * (r3 + s1 * (r4 + s * (r5 + s1 * (r6 + s * r7))))));
    }
    return w;
}

}  // namespace

TEST(Dop853Tableau, TheTreesAreEnumeratedCompletely) {
    const std::vector<Tree> trees = rooted_trees(9);
    std::vector<int> count(10, 0);
    for (const Tree& t : trees) ++count[t.order];
    // the number of rooted trees of each order (OEIS A000081)
    const std::vector<int> expected = {0, 1, 1, 2, 4, 9, 20, 48, 115, 286};
    EXPECT_EQ(count, expected);
    // order 3: the bushy tree (gamma 3) and the tall one (gamma 3!)
    EXPECT_EQ(trees[2].order, 3);
    EXPECT_EQ(trees[2].gamma, 3.0);
    EXPECT_EQ(trees[3].gamma, 6.0);
}

TEST(Dop853Tableau, RowSumsAreTheNodes) {
    for (int i = 0; i < kS; ++i) {
        double sum = 0.0;
        for (int j = 0; j < i; ++j) sum += tableau::a[i][j];
        EXPECT_NEAR(sum, tableau::c[i], 1e-14) << "stage " << i;
    }
    EXPECT_EQ(tableau::c[11], 1.0);
    EXPECT_EQ(tableau::c[12], 1.0);  // row 12 is b: the stage at the step's end, f(t + h, y1)
}

TEST(Dop853Tableau, TheMethodIsOfOrderEightExactly) {
    const std::vector<Tree> trees = rooted_trees(9);
    const std::vector<Weights> phi = elementary_weights(trees);
    const Weights b = weights_b();
    for (int order = 1; order <= 9; ++order) {
        const double worst = worst_residual(trees, phi, b, order, [](const Tree& t) { return 1.0 / t.gamma; });
        std::printf("order %d: worst |b.Phi(t) - 1/gamma(t)| = %.3e\n", order, worst);
        if (order <= 8)
            EXPECT_LT(worst, 1e-13) << order;
        else
            EXPECT_GT(worst, 1e-6);  // not of order 9
    }
    // the bushy trees b^T c^(k-1) = 1/k, written out
    for (int k = 1; k <= 8; ++k) {
        double sum = 0.0;
        for (int i = 0; i < tableau::kStages; ++i) sum += b[i] * std::pow(tableau::c[i], k - 1);
        EXPECT_NEAR(sum, 1.0 / k, 1e-14) << k;
    }
}

TEST(Dop853Tableau, TheErrorEstimatorsAreOfOrdersFiveAndThree) {
    // e5 = b - b5 and e3 = b - bhh (b5, bhh of orders 5 and 3) vanish on the trees through
    // those orders and not beyond
    const std::vector<Tree> trees = rooted_trees(7);
    const std::vector<Weights> phi = elementary_weights(trees);
    Weights e5{}, e3 = weights_b();
    for (int i = 0; i < tableau::kStages; ++i) e5[i] = tableau::e5[i];
    for (int m = 0; m < 3; ++m) e3[tableau::kBhhStage[m]] -= tableau::bhh[m];
    auto zero = [](const Tree&) { return 0.0; };
    for (int order = 1; order <= 6; ++order) {
        const double r5 = worst_residual(trees, phi, e5, order, zero), r3 = worst_residual(trees, phi, e3, order, zero);
        std::printf("order %d: worst |e5.Phi| = %.3e, |e3.Phi| = %.3e\n", order, r5, r3);
        if (order <= 5) EXPECT_LT(r5, 1e-13) << order; else EXPECT_GT(r5, 1e-5) << order;
        if (order <= 3) EXPECT_LT(r3, 1e-13) << order; else EXPECT_GT(r3, 1e-3) << order;
    }
}

TEST(Dop853Tableau, TheContinuousExtensionIsOfOrderSevenAndMeetsTheStepEnds) {
    const std::vector<Tree> trees = rooted_trees(8);
    const std::vector<Weights> phi = elementary_weights(trees);
    for (double s : {0.1, 0.35, 0.5, 0.8}) {
        const Weights w = dense_weights(s);
        for (int order = 1; order <= 8; ++order) {
            const double worst =
                worst_residual(trees, phi, w, order, [&](const Tree& t) { return std::pow(s, t.order) / t.gamma; });
            if (order <= 7)
                EXPECT_LT(worst, 1e-13) << "s = " << s << ", order " << order;
            else
                EXPECT_GT(worst, 1e-7) << "s = " << s;  // of order 7, not 8
        }
    }
    // u(0) = y, u(1) = y1 (the weights b), and C1: u'(0) = f(t, y), u'(1) = f(t + h, y1)
    const Weights b = weights_b(), w0 = dense_weights(0.0), w1 = dense_weights(1.0);
    // (central differences of the polynomials, continued past [0, 1]: error ~ ds^2 |w'''|)
    const double ds = 1e-5;
    const Weights a0 = dense_weights(-ds), b0 = dense_weights(ds), a1 = dense_weights(1.0 - ds),
                  b1 = dense_weights(1.0 + ds);
    for (int i = 0; i < kS; ++i) {
        EXPECT_EQ(w0[i], 0.0) << i;
        EXPECT_NEAR(w1[i], b[i], 1e-14) << i;
        EXPECT_NEAR((b0[i] - a0[i]) / (2 * ds), i == 0 ? 1.0 : 0.0, 1e-6) << i;
        EXPECT_NEAR((b1[i] - a1[i]) / (2 * ds), i == 12 ? 1.0 : 0.0, 1e-6) << i;
    }
}

// ------------------------------------------------------------------ the integrator
namespace {

using Eigen::VectorXd;

using mbd::test::FunctionProblem;
using Outcome = mbd::test::RunResult;

Outcome integrate(const std::string& name, double tol, mbd::OdeProblem& problem, VectorXd y0,
                  const std::vector<double>& outputs) {
    mbd::IntegratorSettings s;
    s.tolerance = tol;
    return mbd::test::run(name, s, problem, 0.0, std::move(y0), outputs);
}

// y' = -y + sin t, y(0) = 2: y = 5/2 e^-t + (sin t - cos t)/2
double smooth_exact(double t) { return 2.5 * std::exp(-t) + 0.5 * (std::sin(t) - std::cos(t)); }
FunctionProblem smooth() {
    return FunctionProblem(1, [](double t, const VectorXd& y, VectorXd& f) { f[0] = -y[0] + std::sin(t); });
}

mbd::SimulationResult simulate(const mbd::Model& model, const std::string& formulation, const std::string& integrator,
                               double tol, double t_end, double output_step, std::vector<mbd::State>& states) {
    const mbd::SimulationSettings s = mbd::test::adaptive_run(formulation, integrator, tol, t_end, output_step);
    states.clear();
    return mbd::simulate(model, mbd::test::shared_registry(), s, [&](const mbd::SimulationSample& sample) {
        states.push_back(sample.state);
        return true;
    });
}

}  // namespace

TEST(Dop853, MeetsTightToleranceWithFewerStepsThanDopri5AndInterpolatesAccurately) {
    // 997 outputs at irregular times, many more than the steps: most from the continuous extension
    std::vector<double> outputs;
    for (int k = 1; k <= 997; ++k) outputs.push_back(10.0 * k / 997.0);
    VectorXd y0(1);
    y0 << 2.0;
    long steps[2] = {0, 0};
    int m = 0;
    for (const char* name : {"dop853", "dopri5"}) {
        FunctionProblem problem = smooth();
        const Outcome r = integrate(name, 1e-10, problem, y0, outputs);
        ASSERT_EQ(r.t.size(), outputs.size());
        double worst = 0.0;
        for (size_t k = 0; k < outputs.size(); ++k) worst = std::max(worst, std::abs(r.y[k][0] - smooth_exact(outputs[k])));
        std::printf("%s tol 1e-10: %ld steps, %ld rejected, %ld rhs; worst error over %zu outputs %.3e\n", name,
                    r.stats.steps, r.stats.rejected_steps, r.stats.rhs_evaluations, outputs.size(), worst);
        EXPECT_LT(worst, 1e-9) << name;
        EXPECT_EQ(r.stats.rhs_evaluations, problem.calls) << name;
        steps[m++] = r.stats.steps;
    }
    EXPECT_LT(3 * steps[0], steps[1]);  // an 8th-order step is much longer at this tolerance
}

// (the projection test of both explicit pairs is in test_integrators.cpp)

TEST(Dop853, TheMaximumStepCountNamesTheIntegrator) {
    FunctionProblem problem = smooth();
    mbd::IntegratorSettings s;
    s.tolerance = 1e-12;
    s.max_steps = 5;
    VectorXd y(1);
    y << 2.0;
    mbd::IntegratorStats stats;
    try {
        mbd::make_integrator("dop853", s)->integrate(problem, 0.0, y, {100.0}, {}, stats);
        FAIL() << "no DynamicsError";
    } catch (const mbd::DynamicsError& e) {
        EXPECT_NE(std::string(e.what()).find("dop853: the maximum number of steps (5)"), std::string::npos) << e.what();
    }
}

// The measured order on IFToMM A01: the bob's position error against the closed form at
// 201 outputs over 4 s (most of them inside steps: the continuous extension, of order 7,
// has a local error O(h^8) like the step's global one), at constant steps h = 0.4 .. 0.05 s:
// max_step = h and a tolerance so loose that every step is accepted and grows to max_step.
// (The slope of error against work over tolerances is no measure of the order here: over
// tolerances 1e-6 .. 1e-12 it came out 9.7 with embedding and 6.4 with augmented.) The
// augmented runs stop at h = 0.1: below, their error falls only slowly (3e-10, 6e-11, 3e-11
// at h = 0.05, 0.025, 0.0125), while embedding reaches 4e-14 at h = 0.025. The bob's inertia
// of 1e-6 puts round-off into the augmented right-hand side, which DOP853's large
// coefficients amplify: with an inertia of 1e-2 the two formulations agree to 6.5e-13 at
// tol 1e-13, with 1e-6 to 1.8e-11 (dopri5: 8e-13 for both).
TEST(Dop853, MeasuredOrderOnA01IsEight) {
    const mbd::Model model = mbd::test::load("dynamics/pendulum-a01.yaml");
    const double t_end = 4.0;
    for (const char* formulation : {"embedding", "augmented"}) {
        const bool augmented = std::string(formulation) == "augmented";
        std::vector<double> errors;
        std::vector<mbd::State> states;
        for (double h : {0.4, 0.2, 0.1, 0.05}) {
            if (augmented && h < 0.1) break;
            // a loose tolerance with the step pinned at h: constant steps
            mbd::SimulationSettings s = mbd::test::adaptive_run(formulation, "dop853", 1e-1, t_end, 0.02);
            s.integration.step = h;
            s.integration.max_step = h;
            states.clear();
            const mbd::SimulationResult r =
                mbd::simulate(model, mbd::test::shared_registry(), s, [&](const mbd::SimulationSample& sample) {
                    states.push_back(sample.state);
                    return true;
                });
            ASSERT_EQ(r.stats.steps, std::lround(t_end / h)) << formulation << " h = " << h;  // constant steps
            EXPECT_EQ(r.stats.rejected_steps, 0);
            double worst = 0.0;
            for (const mbd::State& st : states)
                worst = std::max(worst, (st.q.head<2>() - mbd::test::a01_bob_position(st.t)).norm());
            errors.push_back(worst);
        }
        mbd::test::expect_order_under_halving(errors, 7.5, 8.5, std::string("A01 ") + formulation + " dop853");
    }
}

// The heavy top in steady precession (scenes/dynamics/heavy-top.yaml; book Sec. 8.1): the
// symmetry axis turns about the vertical at the rate phidot from
// (i_zz - I_O) cos(theta) phidot^2 + i_zz psidot phidot = m g l, with no nutation.
TEST(Dop853, HeavyTopStaysInSteadyPrecession) {
    const mbd::Model model = mbd::test::load("dynamics/heavy-top.yaml");
    const double m = 1, l = 0.1, ixx = 0.002 + m * l * l, izz = 0.004, g = 9.81, theta = M_PI / 6, psidot = 100;
    const double a = (izz - ixx) * std::cos(theta), b = izz * psidot, c = -m * g * l;
    const double phidot = (-b + std::sqrt(b * b - 4 * a * c)) / (2 * a);
    std::vector<mbd::State> states;
    double previous = 1.0;
    for (double tol : {1e-7, 1e-10}) {
        const mbd::SimulationResult r = simulate(model, "augmented", "dop853", tol, 5.0, 0.01, states);
        ASSERT_EQ(states.size(), 501u);
        double axis_error = 0.0, nutation = 0.0;
        for (const mbd::State& st : states) {
            const mbd::Vec3 z = mbd::rotation_from_euler_parameters(st.q.segment<4>(3)).col(2);
            const mbd::Vec3 expected =
                Eigen::AngleAxisd(phidot * st.t, mbd::Vec3::UnitZ()) * mbd::Vec3(0, -std::sin(theta), std::cos(theta));
            axis_error = std::max(axis_error, (z - expected).norm());
            nutation = std::max(nutation, std::abs(std::acos(std::clamp(z.z(), -1.0, 1.0)) - theta));
        }
        std::printf("heavy top, dop853 tol %.0e, 5 s: %ld steps, %ld rhs, max axis error %.3e, max nutation %.3e rad\n",
                    tol, r.stats.steps, r.stats.rhs_evaluations, axis_error, nutation);
        EXPECT_LT(axis_error, 1e3 * tol);
        EXPECT_LT(nutation, 1e3 * tol);
        EXPECT_LT(axis_error, previous / 100);  // three decades of tolerance: at least two of error
        previous = axis_error;
    }
}
