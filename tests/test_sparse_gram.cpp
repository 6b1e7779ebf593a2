// The sparse S = J M^-1 J^T of the augmented formulation and the coordinate projection
// (kit/include/mbd/kit/sparse_gram.hpp): its products summed by groups of columns that share
// their rows, W = J Lm formed body by body (a dense block product where J's columns hold W's
// rows, entry by entry where they do not). Oracle: the dense product J M^-1 J^T from the
// System's own mass matrix, and S^-1 b against a dense solve.
#include "support/test_support.hpp"

#include <mbd/model_system.hpp>
#include <mbd/kit/block_mass_inverse.hpp>

#include <mbd/kit/own_order_fill.hpp>
#include <mbd/kit/sparse_gram.hpp>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace {

struct Gram {
    mbd::Model model;
    mbd::ModelSystem system;
    mbd::BlockMassInverse mass_inverse;
    mbd::ConstraintValues cv;
    explicit Gram(const std::string& scene) : model(mbd::test::load(scene)), system(model) {
        mass_inverse.bind(system, "test");
        mbd::State state = system.initial_state();
        system.assemble(state, true);
        system.constraints(state, cv, true);
    }
    Eigen::MatrixXd dense_S(const Eigen::SparseMatrix<double>& J) const {
        const Eigen::MatrixXd Jd(J);
        return Jd * Eigen::MatrixXd(system.mass_matrix()).inverse() * Jd.transpose();
    }
};

// S^-1 b from the sparse factorization against the dense solve of the dense product, and the
// entries of S through S e_k (the solve of S x = S e_k gives e_k back only if S is S)
void expect_same_system(mbd::SparseGram& gram, const Eigen::MatrixXd& S, const char* what) {
    SCOPED_TRACE(what);
    ASSERT_TRUE(gram.factor(0.0));
    EXPECT_NEAR(gram.max_diagonal(), S.diagonal().maxCoeff(), 1e-12 * S.diagonal().maxCoeff());
    const Eigen::Index n = S.rows();
    Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(n, 1.0, 2.0);
    const Eigen::VectorXd expected = S.ldlt().solve(b);
    gram.solve(b, 0);
    EXPECT_LT((b - expected).lpNorm<Eigen::Infinity>(), 1e-9 * expected.lpNorm<Eigen::Infinity>());
    for (Eigen::Index k = 0; k < n; ++k) {
        Eigen::VectorXd x = S.col(k);
        gram.solve(x, 0);
        EXPECT_LT((x - Eigen::VectorXd::Unit(n, k)).lpNorm<Eigen::Infinity>(), 1e-9) << "column " << k;
    }
}

TEST(SparseGram, EqualsTheDenseProductOnPlanarAndSpatialMechanisms) {
    // planar (four-bar loop: bodies with rows of two joints) and spatial (a top with a full
    // inertia tensor, so Lm is not diagonal; the RSSR loop)
    for (const char* scene : {"dynamics/four-bar-conservative.yaml", "dynamics/slider-crank.yaml",
                              "dynamics/rssr-gravity.yaml", "dynamics/heavy-top.yaml"}) {
        Gram g(scene);
        mbd::SparseGram gram;
        gram.analyze(g.system);
        gram.fill(g.cv.J, g.mass_inverse);
        expect_same_system(gram, g.dense_S(g.cv.J), scene);
    }
}

TEST(SparseGram, EntryByEntryWhereTheJacobianLeavesOutRowsOfTheBodyPattern) {
    // J with some structural entries removed (a body column that no longer holds all the rows
    // W's pattern gives its body): W is formed entry by entry there, and S is still J M^-1 J^T
    Gram g("dynamics/rssr-gravity.yaml");
    Eigen::SparseMatrix<double> J = g.cv.J;
    const Eigen::SparseMatrix<double>& full = g.cv.J;
    int removed = 0;  // the first entry of every fourth column
    J.prune([&](Eigen::Index row, Eigen::Index col, double) {
        const bool first = row == full.innerIndexPtr()[full.outerIndexPtr()[col]];
        return !(col % 4 == 1 && first && ++removed);
    });
    J.makeCompressed();
    ASSERT_GT(removed, 0);
    ASSERT_LT(J.nonZeros(), g.cv.J.nonZeros());
    mbd::SparseGram gram;
    gram.analyze(g.system);
    gram.fill(J, g.mass_inverse);
    expect_same_system(gram, g.dense_S(J), "pruned J");
}

TEST(SparseGram, LeftOutRowsAreDecoupled) {
    // a row marked left out has a zero row of W and S's scale on its diagonal: its multiplier
    // is its right-hand side over that scale, the others solve the reduced system
    Gram g("dynamics/four-bar-conservative.yaml");
    const Eigen::Index n = g.cv.J.rows();
    ASSERT_GE(n, 3);
    std::vector<char> left_out(n, 0);
    left_out[1] = 1;
    mbd::SparseGram gram;
    gram.analyze(g.system);
    gram.fill(g.cv.J, g.mass_inverse, &left_out);
    Eigen::SparseMatrix<double> J = g.cv.J;
    J.prune([](Eigen::Index row, Eigen::Index, double) { return row != 1; });
    Eigen::MatrixXd S = g.dense_S(J);
    S(1, 1) = S.diagonal().maxCoeff();
    expect_same_system(gram, S, "row 1 left out");
}

TEST(SparseGram, LongChainInItsOwnOrder) {
    // S = J J^T of a planar chain of 2,600 links (5,200 rows: from kCompareOrderingsFrom rows, the
    // rows' own order, banded, is kept where it fills no more than AMD's), against Eigen's own
    // L D L^T of the product formed by Eigen
    const int links = 2600, rows = 2 * links, cols = 3 * links;
    std::vector<std::vector<int>> rows_of_column(cols);
    std::vector<Eigen::Triplet<double>> entries;
    for (int j = 0; j < links; ++j)
        for (int body = std::max(j - 1, 0); body <= j; ++body)
            for (int c = 0; c < 3; ++c)
                for (int r = 0; r < 2; ++r) {
                    rows_of_column[3 * body + c].push_back(2 * j + r);
                    const double value = (body == j ? 1.0 : -1.0) * (c == r ? 1.0 : 0.05 * (1 + (j + c + r) % 4));
                    entries.emplace_back(2 * j + r, 3 * body + c, value);
                }
    for (std::vector<int>& column : rows_of_column) std::sort(column.begin(), column.end());
    ASSERT_GE(rows, mbd::kCompareOrderingsFrom);
    Eigen::SparseMatrix<double> J(rows, cols);
    J.setFromTriplets(entries.begin(), entries.end());
    J.makeCompressed();

    mbd::SparseGram gram;
    gram.analyze(rows, cols, rows_of_column);
    EXPECT_TRUE(gram.own_order());
    gram.fill(J);
    ASSERT_TRUE(gram.factor(0.0));
    Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(rows, 1.0, 2.0);
    const Eigen::SparseMatrix<double> S = J * J.transpose();
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> oracle(S);
    ASSERT_EQ(oracle.info(), Eigen::Success);
    const Eigen::VectorXd expected = oracle.solve(x);
    gram.solve(x, 0);
    EXPECT_LT((x - expected).lpNorm<Eigen::Infinity>(), 1e-10 * expected.lpNorm<Eigen::Infinity>());
}

// Rank-deficient S = W W^T (redundant constraints): factor(0) refuses it, and the damped
// factorization W W^T + delta I with iterative refinement against the undamped S solves a
// consistent S x = b, Eigen's complete orthogonal decomposition of the dense S giving the
// minimum-norm solution x_min as the oracle. W: 12 rows over 18 columns on a banded pattern,
// row 11 the sum of rows 3 and 7 (dependent), row 5 row 2 plus 1e-3 of a random row (nearly
// dependent: S's least non-zero eigenvalue some 1e-7 of its largest, so that the damping's
// error, of order delta / that eigenvalue, is large before refinement).
//  - Each refinement must shrink the residual b - S x by orders of magnitude (a refinement of
//    the wrong sign grows it), and W^T x (the constraint forces J^T lambda = Lm^-T W^T x of the
//    augmented formulation) must then be W^T x_min to round-off.
//  - x itself is x_min only up to its component in S's null space, where the damped inverse
//    amplifies the round-off of b and of each residual by max diag(S) / delta = 1e12: some 1e-4
//    of |x| (the split of a redundant joint's reactions, which no force depends on; the dense
//    path's pseudo-inverse gives x_min).
TEST(SparseGram, DampedLeastSquaresWithRefinementSolvesRankDeficientSystems) {
    const int rows = 12, cols = 18;
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    Eigen::MatrixXd W = Eigen::MatrixXd::Zero(rows, cols);
    for (int r = 0; r < rows; ++r)
        for (int c = std::max(0, r - 2); c < std::min(cols, r + 5); ++c) W(r, c) = uniform(rng);
    W.row(11) = W.row(3) + W.row(7);
    Eigen::RowVectorXd nudge = Eigen::RowVectorXd::Zero(cols);
    for (int c = 0; c < 7; ++c) nudge[c] = uniform(rng);
    W.row(5) = W.row(2) + 1e-3 * nudge;
    std::vector<std::vector<int>> rows_of_column(cols);
    for (int c = 0; c < cols; ++c)
        for (int r = 0; r < rows; ++r)
            if (W(r, c) != 0.0) rows_of_column[c].push_back(r);
    const Eigen::SparseMatrix<double> Ws = W.sparseView();
    const Eigen::MatrixXd S = W * W.transpose();

    mbd::SparseGram gram;
    gram.analyze(rows, cols, rows_of_column);
    gram.fill(Ws);
    EXPECT_FALSE(gram.factor(0.0));  // row 11 depends on rows 3 and 7
    ASSERT_TRUE(gram.factor(1e-12 * gram.max_diagonal()));

    Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(S);
    cod.setThreshold(1e-12);
    ASSERT_EQ(cod.rank(), rows - 1);
    for (int trial = 0; trial < 3; ++trial) {
        const Eigen::VectorXd b = S * Eigen::VectorXd::NullaryExpr(rows, [&] { return uniform(rng); });  // consistent
        const Eigen::VectorXd minimum_norm = cod.solve(b);
        const Eigen::VectorXd forces = W.transpose() * minimum_norm;
        double residual[4], force[4], error[4];
        for (int refinements = 0; refinements < 4; ++refinements) {
            Eigen::VectorXd x = b;
            gram.solve(x, refinements);
            residual[refinements] = (b - S * x).norm() / b.norm();
            force[refinements] = (W.transpose() * x - forces).norm() / forces.norm();
            error[refinements] = (x - minimum_norm).norm() / minimum_norm.norm();
        }
        std::printf("trial %d after 0 to 3 refinements: |b - S x| / |b| %.2e %.2e %.2e %.2e; |W^T (x - x_min)| / "
                    "|W^T x_min| %.2e %.2e %.2e %.2e; |x - x_min| / |x_min| %.2e %.2e %.2e %.2e\n",
                    trial, residual[0], residual[1], residual[2], residual[3], force[0], force[1], force[2], force[3],
                    error[0], error[1], error[2], error[3]);
        EXPECT_GT(force[0], 1e-10);  // the damping alone is off: the refinement has work to do
        EXPECT_LT(residual[1], 1e-3 * residual[0]);
        EXPECT_LT(force[1], 1e-3 * force[0]);
        for (int k = 2; k < 4; ++k) {
            EXPECT_LT(residual[k], 1e-14);
            EXPECT_LT(force[k], 1e-11);
            EXPECT_LT(error[k], 1e-3);
        }
    }
}

// The same against a mechanism's own J M^-1 J^T: the orthogonal Bricard linkage, whose six
// revolute joints give 30 rows of rank 29 at its assembled configuration.
TEST(SparseGram, DampedLeastSquaresSolvesTheBricardsRedundantRows) {
    Gram g("book/bricard.yaml");
    mbd::SparseGram gram;
    gram.analyze(g.system);
    gram.fill(g.cv.J, g.mass_inverse);
    const Eigen::MatrixXd S = g.dense_S(g.cv.J);
    ASSERT_EQ(S.rows(), 30);
    EXPECT_FALSE(gram.factor(0.0));
    ASSERT_TRUE(gram.factor(1e-12 * gram.max_diagonal()));
    Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(S);
    cod.setThreshold(1e-10);
    ASSERT_EQ(cod.rank(), 29);
    const Eigen::MatrixXd Jd(g.cv.J);
    const Eigen::VectorXd b = S * Eigen::VectorXd::LinSpaced(30, -1.0, 2.0);
    const Eigen::VectorXd minimum_norm = cod.solve(b), forces = Jd.transpose() * minimum_norm;
    double residual[3], force[3];
    for (int refinements = 0; refinements < 3; ++refinements) {
        Eigen::VectorXd x = b;
        gram.solve(x, refinements);
        residual[refinements] = (b - S * x).norm() / b.norm();
        force[refinements] = (Jd.transpose() * x - forces).norm() / forces.norm();
    }
    std::printf("Bricard after 0 to 2 refinements: |b - S x| / |b| %.2e %.2e %.2e, |J^T (x - x_min)| / |J^T x_min| "
                "%.2e %.2e %.2e\n",
                residual[0], residual[1], residual[2], force[0], force[1], force[2]);
    EXPECT_LT(residual[1], 1e-2 * residual[0]);
    EXPECT_LT(residual[2], 1e-14);
    EXPECT_LT(force[2], 1e-11);
}

}  // namespace
