// The hamiltonian formulation (book Sec. 5.10, Eq. 5.179), embedded on the independent
// coordinates of a coordinate partition: y holds momenta, H is conserved on a
// conservative closed loop, pdot is the time derivative of p along the true motion
// (an independent finite-difference check of the Bdot term, planar and spatial), the
// accelerations agree with the augmented formulation, and `--diagnostics` writes H.
#include <mbd/model_system.hpp>
#include <mbd/simulation.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

#include "support/test_support.hpp"

namespace {

using mbd::test::Csv;
using mbd::test::load;
using mbd::test::make_formulation;
using mbd::test::read_csv;
using mbd::test::scratch;

namespace fs = std::filesystem;
using mbd::test::run_mbd;
using mbd::test::shared_registry;

mbd::State assembled(mbd::System& system) {
    mbd::State s = system.initial_state();
    s.t = 0.0;
    system.assemble(s, true);
    system.consistent_velocities(s, true);
    return s;
}

TEST(Hamiltonian, StateHoldsTheMomentaOfThePendulum) {
    // one revolute joint: the independent coordinate is the angle, p = J_O omega
    const mbd::Model model = load("dynamics/pendulum-a01.yaml");
    mbd::ModelSystem system(model);
    mbd::Param node;
    auto h = make_formulation("hamiltonian", node);
    h->bind(system, {});
    EXPECT_TRUE(h->has_hamiltonian());
    mbd::State s = assembled(system);
    s.v << 0.0, 2.0, 2.0;  // omega = 2 about the pivot at (0, 0), bob at (1, 0): v = omega z x r
    Eigen::VectorXd y;
    h->to_ode(s, y);
    ASSERT_EQ(y.size(), system.nq() + 1);
    const double J_O = 1e-6 + 1.0;
    // p = J_O omega, stored divided by the generalized mass of the partition (J_O): omega
    EXPECT_NEAR(y[system.nq()] * J_O, J_O * 2.0, 1e-12);
    EXPECT_NEAR(y[system.nq()], 2.0, 1e-12);
    // H = p^2 / (2 J_O) + V
    EXPECT_NEAR(h->hamiltonian(0.0, y), 0.5 * J_O * 4.0 + system.potential_energy(s), 1e-12);
    mbd::State back;
    h->from_ode(0.0, y, back);
    EXPECT_LT((back.v - s.v).lpNorm<Eigen::Infinity>(), 1e-12);
}

// A dopri5 run of the hamiltonian formulation with --diagnostics (H, T, V columns) to t_end,
// a row every output_step: its result and its CSV
struct DiagnosedRun {
    mbd::SimulationResult result;
    Csv csv;
};
DiagnosedRun diagnosed_run(const mbd::Model& model, const std::string& name, double tolerance, double t_end,
                           double output_step) {
    const fs::path dir = scratch(name);
    mbd::SimulationSettings s = mbd::test::adaptive_run("hamiltonian", "dopri5", tolerance, t_end, output_step);
    s.diagnostics = true;
    const std::unique_ptr<mbd::OutputSink> csv = mbd::csv_output_format().make(dir / "h.csv");
    DiagnosedRun run{mbd::simulate(model, shared_registry(), s, {}, {csv.get()}), {}};
    run.csv = read_csv(dir / "h.csv");
    return run;
}

TEST(Hamiltonian, ConservesHOnTheConservativeFourBar) {
    // four-bar under gravity, no damping: H = T + V constant to 1e-8 over 10 s (dopri5, tol 1e-12)
    const mbd::Model model = load("dynamics/four-bar-conservative.yaml");
    const DiagnosedRun run = diagnosed_run(model, "four-bar", 1e-12, 10.0, 0.01);
    const mbd::SimulationResult& r = run.result;
    const Csv& csv = run.csv;
    const int H = csv.column("H"), T = csv.column("kinetic_energy"), V = csv.column("potential_energy");
    ASSERT_GE(H, 0) << "no H column with --diagnostics";
    ASSERT_EQ(csv.rows.size(), 1001u);
    const double H0 = csv.rows.front()[H];
    double drift = 0.0, vs_energy = 0.0, span = 0.0, T0 = csv.rows.front()[T];
    for (const auto& row : csv.rows) {
        drift = std::max(drift, std::abs(row[H] - H0));
        vs_energy = std::max(vs_energy, std::abs(row[H] - row[T] - row[V]));
        span = std::max(span, std::abs(row[T] - T0));
    }
    std::printf("four-bar-conservative hamiltonian 10 s dopri5 tol 1e-12: max |H - H0| = %.3e (H0 = %.6f, T varies by %.3f), "
                "max |H - (T + V)| = %.3e, %ld steps, cpu %.3f s, final |C| %.1e\n",
                drift, H0, span, vs_energy, r.stats.steps, r.cpu_seconds, r.final_position_violation);
    EXPECT_GT(span, 0.1);  // the motion is not trivial
    EXPECT_LT(drift, 1e-8);
    EXPECT_LT(vs_energy, 1e-10);
}

TEST(Hamiltonian, SparsePathCarriesFortyFourBarsThroughTheirDeadPoints) {
    // IFToMM A02 with 40 loops (243 velocity coordinates: the sparse path, one freedom). At the
    // all-horizontal position (t ~ 0.72 s) J loses 40 in rank; the motion is the parallelogram's,
    // a conservative 1-DOF pendulum, so T + V must hold through it (the stability case's bound,
    // 1e-6 of max(T + |V|)), and so must H = T + V itself
    const mbd::Model model = load("extreme/a02-four-bar-40-singular.yaml");
    mbd::ModelSystem system(model);
    ASSERT_GT(system.nv(), mbd::kDefaultSparseThreshold);
    const DiagnosedRun run = diagnosed_run(model, "a02-40", 1e-10, 1.0, 0.01);
    const mbd::SimulationResult& r = run.result;
    const Csv& csv = run.csv;
    ASSERT_EQ(csv.rows.size(), 101u);
    const int H = csv.column("H"), T = csv.column("kinetic_energy"), V = csv.column("potential_energy");
    const int y0 = csv.column("crank0.y");
    const double E0 = csv.rows.front()[T] + csv.rows.front()[V];
    double drift = 0.0, scale = 0.0, vs_energy = 0.0, lowest = csv.rows.front()[y0];
    for (const auto& row : csv.rows) {
        drift = std::max(drift, std::abs(row[T] + row[V] - E0));
        scale = std::max(scale, row[T] + std::abs(row[V]));
        vs_energy = std::max(vs_energy, std::abs(row[H] - row[T] - row[V]));
        lowest = std::min(lowest, row[y0]);
    }
    std::printf("a02-four-bar-40 hamiltonian (sparse) dopri5 tol 1e-10 to 1 s: energy drift %.3e of %.3f, max |H - (T + V)| "
                "%.3e, %ld steps, cpu %.3f s\n",
                drift, scale, vs_energy, r.stats.steps, r.cpu_seconds);
    EXPECT_LT(lowest, -0.1) << "the cranks did not pass the horizontal dead point";
    EXPECT_LT(drift, 1e-6 * scale);
    EXPECT_LT(vs_energy, 1e-8 * scale);
}

// pdot from the formulation against d/dt (B^T M v) along the motion, by central
// differences of to_ode over (q, v) advanced with (v, vdot of the augmented formulation):
// an independent check of -dH/dq (its Bdot term: the polarization of gamma and, for
// spatial bodies, the Lie bracket of the angular velocities).
// Both paths: the dense one (Bdot by 2k constraint evaluations) and the sparse one (Jdot^T mu of
// jdot_transpose.hpp: the joints' own (d gamma / d v)^T mu beside coloured polarization).
class MomentumRate : public ::testing::TestWithParam<std::tuple<std::string, mbd::LinearAlgebra>> {};

TEST_P(MomentumRate, EqualsTheTimeDerivativeOfTheMomenta) {
    const auto& [scene, algebra] = GetParam();
    const mbd::Model model = load(scene);
    mbd::ModelSystem system(model);
    mbd::Param n1, n2;
    auto h = make_formulation("hamiltonian", n1);
    auto aug = make_formulation("augmented", n2);
    mbd::FormulationOptions options;
    options.algebra = algebra;
    h->bind(system, options);
    aug->bind(system, {});
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    double worst = 0.0, worst_acc = 0.0;
    for (int trial = 0; trial < 5; ++trial) {
        mbd::State s = assembled(system);
        Eigen::VectorXd dq(system.nv());
        for (int k = 0; k < dq.size(); ++k) dq[k] = 0.1 * u(rng);
        system.advance_positions(s.q, dq);
        system.assemble(s, true);
        for (int k = 0; k < s.v.size(); ++k) s.v[k] = 2.0 * u(rng);
        system.consistent_velocities(s, true);
        Eigen::VectorXd y, ydot, vdot, vdot_h;
        h->to_ode(s, y);
        h->rhs(0.0, y, ydot);
        aug->accelerations(s, vdot);
        h->accelerations(s, vdot_h);
        worst_acc = std::max(worst_acc, (vdot_h - vdot).lpNorm<Eigen::Infinity>() / std::max(1.0, vdot.lpNorm<Eigen::Infinity>()));
        const int k = static_cast<int>(y.size()) - system.nq();
        const double step = 1e-5;  // the difference error is O(step^2): 1e-4 gives 5e-7 on the RSSR, 1e-5 5e-9
        Eigen::VectorXd p[2];
        for (int side = 0; side < 2; ++side) {
            const double sgn = side == 0 ? 1.0 : -1.0;
            // second order along the motion: q(t + e) = q (+) (e v + e^2/2 vdot), v(t + e) = v + e vdot
            mbd::State m = s;
            system.advance_positions(m.q, sgn * step * s.v + 0.5 * step * step * vdot);
            m.v = s.v + sgn * step * vdot;
            Eigen::VectorXd ym;
            h->to_ode(m, ym);
            p[side] = ym.tail(k);
        }
        const Eigen::VectorXd fd = (p[0] - p[1]) / (2 * step);
        const Eigen::VectorXd pdot = ydot.tail(k);
        worst = std::max(worst, (pdot - fd).lpNorm<Eigen::Infinity>() / std::max(1.0, fd.lpNorm<Eigen::Infinity>()));
    }
    std::printf("%-36s %-6s |pdot - d/dt (B^T M v)| / scale = %.2e, |vdot - vdot_augmented| / scale = %.2e\n",
                scene.c_str(), algebra == mbd::LinearAlgebra::Sparse ? "sparse" : "dense", worst, worst_acc);
    EXPECT_LT(worst, 1e-7);
    EXPECT_LT(worst_acc, 1e-10);
}

INSTANTIATE_TEST_SUITE_P(Scenes, MomentumRate,
                         ::testing::Combine(
                             ::testing::Values("dynamics/four-bar-conservative.yaml", "dynamics/slider-crank.yaml",
                                               "dynamics/rssr-gravity.yaml", "dynamics/heavy-top.yaml",
                                               "dynamics/torque-free-body.yaml",
                                               // joints that give (d gamma / d v)^T mu themselves (pins, joints of
                                               // spatial primitives) beside probed ones and drivers
                                               "bench/chain-5.yaml", "bench/a05-flyball.yaml", "bench/car-axis.yaml",
                                               "bench/a04-bricard.yaml"),
                             ::testing::Values(mbd::LinearAlgebra::Dense, mbd::LinearAlgebra::Sparse)),
                         [](const ::testing::TestParamInfo<std::tuple<std::string, mbd::LinearAlgebra>>& info) {
                             std::string name = fs::path(std::get<0>(info.param)).stem().string();
                             for (char& c : name)
                                 if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                             return name + (std::get<1>(info.param) == mbd::LinearAlgebra::Sparse ? "_sparse" : "_dense");
                         });

TEST(HamiltonianCli, DiagnosticsWriteAnHColumnOnlyWhenTheFormulationHasOne) {
    const fs::path dir = scratch("cli");
    const std::string scene = mbd::test::scene_path("dynamics/pendulum-a01.yaml").string();
    const auto r = run_mbd("simulate " + scene + " --formulation hamiltonian --diagnostics --tol 1e-10 --t-end 1 -q -o " +
                           (dir / "h.csv").string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const Csv with = read_csv(dir / "h.csv");
    const int H = with.column("H");
    ASSERT_GE(H, 0);
    EXPECT_EQ(H, static_cast<int>(with.header.size()) - 1);  // the last column
    for (const auto& row : with.rows) EXPECT_NEAR(row[H], 0.0, 1e-8);  // T + V = 0 for A01
    const auto a = run_mbd("simulate " + scene + " --formulation augmented --diagnostics --t-end 1 -q -o " +
                           (dir / "a.csv").string());
    ASSERT_EQ(a.exit_code, 0) << a.err;
    EXPECT_EQ(read_csv(dir / "a.csv").column("H"), -1);
}

}  // namespace
