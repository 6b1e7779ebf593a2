// x = A^+ b, the minimum-norm least-squares solution, from a complete orthogonal
// decomposition A P = Q [T 0; 0 0] Z^* (Eigen's CompleteOrthogonalDecomposition), with
// workspace sized once: unlike the decomposition's own solve(), it allocates nothing, so
// formulations can use it on their evaluation path (rank-deficient constraint Jacobians).
#pragma once

#include <Eigen/Dense>

#include <algorithm>

namespace mbd {

class PseudoInverseSolver {
public:
    using Decomposition = Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>;

    // Workspace for a decomposition of a rows x cols matrix.
    void resize(int rows, int cols) {
        c_.setZero(rows);
        y_.setZero(cols);
        householder_.setZero(std::max(cols, 1));
    }
    // x = A^+ b; b and x must not be the same vector.
    void solve(const Decomposition& cod, const Eigen::VectorXd& b, Eigen::VectorXd& x) {
        const Eigen::Index rank = cod.rank(), cols = cod.cols();
        if (rank == 0) {
            x.setZero(cols);
            return;
        }
        // c = Q^* b: the first `rank` reflectors of Q in turn (Q = H_0 H_1 ..., each H_k symmetric)
        c_ = b;
        const auto Q = cod.householderQ();
        for (Eigen::Index k = 0; k < rank; ++k)
            c_.tail(c_.size() - k).applyHouseholderOnTheLeft(Q.essentialVector(k), cod.hCoeffs()(k), householder_.data());
        y_.head(rank) = c_.head(rank);  // T z = c(1:rank)
        cod.matrixQTZ().topLeftCorner(rank, rank).triangularView<Eigen::Upper>().solveInPlace(y_.head(rank));
        y_.tail(cols - rank).setZero();
        if (rank < cols) {
            // y = Z [z; 0], the reflectors of Z applied in turn (Eigen's applyZAdjointOnTheLeftInPlace)
            for (Eigen::Index k = 0; k < rank; ++k) {
                if (k != rank - 1) std::swap(y_[k], y_[rank - 1]);
                y_.segment(rank - 1, cols - rank + 1)
                    .applyHouseholderOnTheLeft(cod.matrixQTZ().row(k).tail(cols - rank).adjoint(), cod.zCoeffs()(k),
                                               householder_.data());
                if (k != rank - 1) std::swap(y_[k], y_[rank - 1]);
            }
        }
        x.noalias() = cod.colsPermutation() * y_;  // undo the column pivoting
    }

private:
    Eigen::VectorXd c_, y_, householder_;
};

}  // namespace mbd
