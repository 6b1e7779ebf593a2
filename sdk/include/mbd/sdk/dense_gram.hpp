// S = W W^T for a dense W: the constraint rows' matrix in the kinetic-energy metric,
// S = J M^-1 J^T with W = J Lm (M^-1 = Lm Lm^T), of the augmented formulation (book
// Eq. 6.141) and of the coordinate projection (projection.hpp). Factored L D L^T with
// symmetric pivoting; (nearly) rank deficient, solved through the minimum-norm
// S^+ = (W^T)^+ W^+ from complete orthogonal decompositions of W, whose condition is the
// square root of S's (singular values below 1e-10 of the largest count as zero). All
// storage is sized by resize(): factoring and solving allocate nothing.
#pragma once

#include <mbd/sdk/pseudo_inverse.hpp>

#include <Eigen/Dense>

#include <vector>

namespace mbd {

class DenseGram {
public:
    void resize(int rows, int cols) {
        W_.setZero(rows, cols);
        Wt_.setZero(cols, rows);
        S_.setZero(rows, rows);
        w_.setZero(cols);
        // size the factorizations' storage once by computing on zeros (a size-constructed
        // Eigen decomposition leaves its status uninitialized: undefined behaviour when copied)
        if (rows > 0) {
            ldlt_.compute(S_);
            cod_w_.compute(W_);
            cod_wt_.compute(W_.transpose());
        }
        pinv_w_.resize(rows, cols);
        pinv_wt_.resize(cols, rows);
        pseudo_ = false;
    }

    // W, filled by the caller before factoring.
    Eigen::MatrixXd& W() { return W_; }

    // S = W W^T, with the decoupled rows (their rows of W zero) given a unit diagonal scaled
    // to S, so that their solution is their right-hand side over that scale (the caller zeroes
    // it); then L D L^T. Returns min D / max |D|, or 0 when the factorization failed: at or
    // below about 1e-8, S is (nearly) rank deficient.
    double factor_ldlt(const std::vector<int>& decoupled = {}) {
        pseudo_ = false;
        if (S_.rows() == 0) return 1.0;
        // the lower triangle of W W^T as dot products of W's rows, each contiguous in Wt_: a
        // blocked product (rankUpdate) allocates its packing buffers on the heap once W passes
        // a few hundred entries
        Wt_ = W_.transpose();
        S_.triangularView<Eigen::Lower>() = Wt_.transpose().lazyProduct(Wt_);
        if (!decoupled.empty()) {
            const double unit = std::max(S_.diagonal().maxCoeff(), 1e-300);
            for (int r : decoupled) S_(r, r) = unit;
        }
        ldlt_.compute(S_);
        const auto D = ldlt_.vectorD();
        const double dmax = D.cwiseAbs().maxCoeff();
        if (ldlt_.info() != Eigen::Success || !(dmax > 0)) return 0.0;
        return D.minCoeff() / dmax;
    }
    // The minimum-norm path instead (after factor_ldlt() or on its own).
    void factor_pseudo_inverse() {
        cod_w_.setThreshold(1e-10);
        cod_wt_.setThreshold(1e-10);
        cod_w_.compute(W_);
        cod_wt_.compute(W_.transpose());
        pseudo_ = true;
    }
    bool pseudo_inverse() const { return pseudo_; }

    // x <- S^-1 x, or S^+ x after factor_pseudo_inverse().
    void solve(Eigen::VectorXd& x) {
        if (x.size() == 0) return;
        if (pseudo_) {
            pinv_w_.solve(cod_w_, x, w_);   // W^+ x
            pinv_wt_.solve(cod_wt_, w_, x);  // (W^T)^+ W^+ x
        } else {
            ldlt_.solveInPlace(x);
        }
    }

private:
    Eigen::MatrixXd W_, Wt_, S_;
    Eigen::VectorXd w_;
    Eigen::LDLT<Eigen::MatrixXd> ldlt_;
    Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod_w_, cod_wt_;
    PseudoInverseSolver pinv_w_, pinv_wt_;
    bool pseudo_ = false;
};

}  // namespace mbd
