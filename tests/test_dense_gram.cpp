// The dense S = J M^-1 J^T of the augmented formulation and the projection (kit dense_gram.hpp):
// formed by body blocks, it equals the product of the dense matrices; its pivoted Cholesky
// solves S x = b as a full-pivoting LU does; and the ratio that decides the minimum-norm path
// is about the inverse condition of the equilibrated S (an SVD here is the oracle), so a badly
// scaled but well-conditioned S (the car axis) keeps the fast path and a truly ill-conditioned
// one (the chain with mass ratios 1e6 and 1e-6) does not.
#include "support/test_support.hpp"

#include <mbd/model_system.hpp>
#include <mbd/kit/block_mass_inverse.hpp>
#include <mbd/kit/dense_gram.hpp>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <string>

namespace {

struct Gram {
    mbd::Model model;
    mbd::ModelSystem system;
    mbd::BlockMassInverse mass_inverse;
    mbd::DenseGram gram;
    mbd::ConstraintValues cv;
    Eigen::MatrixXd S;  // J M^-1 J^T by dense products

    explicit Gram(const std::string& path) : model(mbd::test::load(path)), system(model) {
        mass_inverse.bind(system, "test");
        gram.resize(system.constraint_rows(true), system.nv());
        mbd::State state = system.initial_state();
        system.assemble(state, true);
        system.constraints(state, cv, true);
        const Eigen::MatrixXd J(cv.J);
        const Eigen::MatrixXd Minv = Eigen::MatrixXd(system.mass_matrix()).inverse();
        S = J * Minv * J.transpose();
    }
    // the condition of D S D, D = diag(S)^-1/2
    double equilibrated_condition() const {
        const Eigen::VectorXd d = S.diagonal().cwiseSqrt().cwiseInverse();
        const Eigen::MatrixXd E = d.asDiagonal() * S * d.asDiagonal();
        const Eigen::VectorXd s = Eigen::JacobiSVD<Eigen::MatrixXd>(E).singularValues();
        return s(0) / s(s.size() - 1);
    }
};

TEST(DenseGram, SolvesAsAFullPivotingLuOnTheCarAxisDespiteItsScaling) {
    Gram g("bench/car-axis.yaml");
    const double ratio = g.gram.factor(g.cv.J, g.mass_inverse);
    const Eigen::VectorXd unequilibrated = Eigen::JacobiSVD<Eigen::MatrixXd>(g.S).singularValues();
    EXPECT_GT(unequilibrated(0) / unequilibrated(unequilibrated.size() - 1), 1e8)
        << "the car axis's S is badly scaled: the case this test is about";
    EXPECT_LT(g.equilibrated_condition(), 1e7);
    EXPECT_GT(ratio, 1e-8) << "a well-conditioned S keeps the Cholesky path";
    EXPECT_GT(ratio, 0.1 / g.equilibrated_condition());
    EXPECT_TRUE(g.gram.well_conditioned());
    const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(g.S.rows(), 1.0, 2.0);
    Eigen::VectorXd x = b;
    g.gram.solve(x);
    const Eigen::VectorXd reference = g.S.fullPivLu().solve(b);
    EXPECT_LT((x - reference).norm(), 1e-8 * reference.norm());
}

TEST(DenseGram, SendsTheMassRatioChainToTheMinimumNormPath) {
    Gram g("extreme/mass-ratio-chain.yaml");
    const double ratio = g.gram.factor(g.cv.J, g.mass_inverse);
    EXPECT_GT(g.equilibrated_condition(), 1e10);
    EXPECT_LE(ratio, 1e-8);
    EXPECT_LE(ratio, 10.0 / g.equilibrated_condition() * g.S.rows());
}

TEST(DenseGram, BodyBlocksEqualTheDenseProduct) {
    for (const char* path : {"bench/a05-flyball.yaml", "bench/chain-5.yaml", "dynamics/slider-crank.yaml"}) {
        SCOPED_TRACE(path);
        Gram g(path);
        ASSERT_GT(g.gram.factor(g.cv.J, g.mass_inverse), 1e-8);
        // S is symmetric positive definite here: S x = e_k for every k gives S^-1, whose inverse is S
        Eigen::MatrixXd inverse(g.S.rows(), g.S.cols());
        for (Eigen::Index k = 0; k < g.S.rows(); ++k) {
            Eigen::VectorXd x = Eigen::VectorXd::Unit(g.S.rows(), k);
            g.gram.solve(x);
            inverse.col(k) = x;
        }
        const Eigen::MatrixXd product = g.S * inverse;
        EXPECT_LT((product - Eigen::MatrixXd::Identity(g.S.rows(), g.S.cols())).cwiseAbs().maxCoeff(), 1e-8);
    }
}

}  // namespace
