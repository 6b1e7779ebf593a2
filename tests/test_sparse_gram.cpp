// The sparse S = J M^-1 J^T of the augmented formulation and the coordinate projection
// (formulations/support/sparse_gram.hpp): its products summed by groups of columns that share
// their rows, W = J Lm formed body by body (a dense block product where J's columns hold W's
// rows, entry by entry where they do not). Oracle: the dense product J M^-1 J^T from the
// System's own mass matrix, and S^-1 b against a dense solve.
#include "support/test_support.hpp"

#include <mbd/model_system.hpp>
#include <mbd/sdk/block_mass_inverse.hpp>

#include <own_order_fill.hpp>
#include <sparse_gram.hpp>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>

#include <gtest/gtest.h>

#include <algorithm>
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

}  // namespace
