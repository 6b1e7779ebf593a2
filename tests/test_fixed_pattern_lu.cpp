// The sparse LU on a fixed pattern (kit/include/mbd/kit/fixed_pattern_lu.hpp) and the fill of an
// order (own_order_fill.hpp). From 5,000 rows the LU keeps K's own order where it fills (almost)
// no more than AMD's, for locality; it must never try an order that fills a dense block, and
// whichever order it keeps must solve K x = b to round-off, refactored with new values too.
// Oracles: the fill of the Cholesky factor in closed form (tridiagonal and arrow patterns), the
// entries KLU itself gives AMD's order and K's own order, and residuals.
#include <mbd/kit/fixed_pattern_lu.hpp>
#include <mbd/kit/own_order_fill.hpp>

#include <Eigen/SparseCore>

#include <gtest/gtest.h>

#include <klu.h>

#include <cmath>
#include <vector>

namespace {

using Sparse = Eigen::SparseMatrix<double>;

Sparse from(int n, const std::vector<Eigen::Triplet<double>>& entries) {
    Sparse K(n, n);
    K.setFromTriplets(entries.begin(), entries.end());
    K.makeCompressed();
    return K;
}

// A tridiagonal matrix (a chain of n unknowns), diagonally dominant
Sparse tridiagonal(int n) {
    std::vector<Eigen::Triplet<double>> e;
    for (int k = 0; k < n; ++k) {
        e.emplace_back(k, k, 4.0 + k % 3);
        if (k > 0) e.emplace_back(k, k - 1, -1.0 - 0.1 * (k % 5));
        if (k + 1 < n) e.emplace_back(k, k + 1, -1.0);
    }
    return from(n, e);
}

// An arrow: unknown `hub` coupled to every other one (a body jointed to all the others)
Sparse arrow(int n, int hub) {
    std::vector<Eigen::Triplet<double>> e;
    for (int k = 0; k < n; ++k) {
        e.emplace_back(k, k, k == hub ? 2.0 * n : 3.0 + k % 4);
        if (k != hub) {
            e.emplace_back(k, hub, 1.0);
            e.emplace_back(hub, k, 0.5);
        }
    }
    return from(n, e);
}

// The amalgamated block system (Eq. 4.20) of a planar chain of `links` bodies (3 velocities
// each) held by revolute-like joints (2 rows over the 3 velocities of each of their two bodies;
// the first joint holds body 0 to the ground), in that formulation's order (velocities, then
// multipliers):
//     [ M  J^T ]
//     [ J  0   ]
Sparse chain_saddle_point(int links, double scale) {
    std::vector<Eigen::Triplet<double>> e;
    const int n = 3 * links, m = 2 * links;
    for (int c = 0; c < n; ++c) e.emplace_back(c, c, c % 3 == 2 ? 0.01 + 0.001 * (c % 5) : 1.0);
    for (int j = 0; j < links; ++j)
        for (int r = 0; r < 2; ++r) {
            const int row = n + 2 * j + r;
            for (int body = j - 1; body <= j; ++body) {
                if (body < 0) continue;
                for (int c = 0; c < 3; ++c) {
                    const double a = scale * (body == j ? 1.0 : -1.0) * (c == r ? 1.0 : 0.05 * (1 + (j + c) % 3));
                    e.emplace_back(row, 3 * body + c, a);
                    e.emplace_back(3 * body + c, row, a);
                }
            }
        }
    return from(n + m, e);
}

// entries of L and U from KLU itself: in AMD's order (its default), or in K's own order
long klu_entries(Sparse& K, bool own_order) {
    klu_common common;
    klu_defaults(&common);
    const int n = static_cast<int>(K.rows());
    klu_symbolic* symbolic = own_order ? klu_analyze_given(n, K.outerIndexPtr(), K.innerIndexPtr(), nullptr, nullptr, &common)
                                       : klu_analyze(n, K.outerIndexPtr(), K.innerIndexPtr(), &common);
    klu_numeric* numeric = klu_factor(K.outerIndexPtr(), K.innerIndexPtr(), K.valuePtr(), symbolic, &common);
    const long entries = numeric ? static_cast<long>(numeric->lnz) + numeric->unz : -1;
    if (numeric) klu_free_numeric(&numeric, &common);
    klu_free_symbolic(&symbolic, &common);
    return entries;
}

// || K x - b ||_inf / (||K||_inf ||x||_inf + ||b||_inf) after solving with `lu`
double backward_error(mbd::FixedPatternLU& lu, const Sparse& K) {
    Eigen::VectorXd b(K.rows());
    for (Eigen::Index k = 0; k < b.size(); ++k) b[k] = 1.0 + std::sin(0.37 * static_cast<double>(k));
    Eigen::VectorXd x = b;
    EXPECT_TRUE(lu.solve(x));
    const Eigen::VectorXd r = K * x - b;
    Eigen::VectorXd row_sums = Eigen::VectorXd::Zero(K.rows());
    for (Eigen::Index c = 0; c < K.outerSize(); ++c)
        for (Sparse::InnerIterator it(K, c); it; ++it) row_sums[it.row()] += std::abs(it.value());
    return r.lpNorm<Eigen::Infinity>() /
           (row_sums.maxCoeff() * x.lpNorm<Eigen::Infinity>() + b.lpNorm<Eigen::Infinity>());
}

TEST(OwnOrderFill, CholeskyEntriesOfTridiagonalAndArrowPatterns) {
    const long n = 200;
    // a chain: no fill, n diagonal entries and n - 1 below
    EXPECT_EQ(mbd::own_order_cholesky_entries(tridiagonal(static_cast<int>(n))), 2 * n - 1);
    // the hub last: no fill either; first: the whole lower triangle fills
    EXPECT_EQ(mbd::own_order_cholesky_entries(arrow(static_cast<int>(n), static_cast<int>(n) - 1)), 2 * n - 1);
    EXPECT_EQ(mbd::own_order_cholesky_entries(arrow(static_cast<int>(n), 0)), n * (n + 1) / 2);
}

TEST(FixedPatternLU, KeepsTheChainsOwnOrderAndSolvesWithItAfterNewValues) {
    Sparse K = chain_saddle_point(2000, 1.0);  // 10,000 rows
    ASSERT_GE(K.rows(), mbd::kCompareOrderingsFrom);
    const long amd = klu_entries(K, false), own = klu_entries(K, true);
    ASSERT_GT(amd, 0);
    ASSERT_GT(own, 0);
    ASSERT_LE(own, mbd::kOwnOrderSlack * amd);  // the case this test is about

    mbd::FixedPatternLU lu;
    ASSERT_TRUE(lu.analyze(K));
    ASSERT_TRUE(lu.factor(K, true));
    EXPECT_EQ(lu.factor_entries(), own);
    EXPECT_LT(backward_error(lu, K), 1e-13);

    // new values on the same pattern, refactored with the kept order's pivots
    Sparse K2 = chain_saddle_point(2000, 2.5);
    ASSERT_TRUE(lu.factor(K2, false));
    EXPECT_LT(backward_error(lu, K2), 1e-13);
}

TEST(FixedPatternLU, NeverFactorsAnOrderThatFillsADenseBlock) {
    // the hub first: K's own order fills the whole matrix (n^2 / 2 entries, n^3 / 3 work: minutes
    // at this size, which the test's time limit would catch); AMD puts the hub last
    Sparse K = arrow(8000, 0);
    mbd::FixedPatternLU lu;
    ASSERT_TRUE(lu.analyze(K));
    ASSERT_TRUE(lu.factor(K, true));
    EXPECT_EQ(lu.factor_entries(), klu_entries(K, false));
    EXPECT_LT(lu.factor_entries(), 5 * K.rows());  // a dense block: 32 million
    EXPECT_LT(backward_error(lu, K), 1e-13);
}

TEST(FixedPatternLU, SmallSystemsKeepAmdsOrder) {
    Sparse K = chain_saddle_point(300, 1.0);  // 1,500 rows: below the comparison
    ASSERT_LT(K.rows(), mbd::kCompareOrderingsFrom);
    mbd::FixedPatternLU lu;
    ASSERT_TRUE(lu.analyze(K));
    ASSERT_TRUE(lu.factor(K, true));
    EXPECT_EQ(lu.factor_entries(), klu_entries(K, false));
    EXPECT_LT(backward_error(lu, K), 1e-13);
}

}  // namespace
