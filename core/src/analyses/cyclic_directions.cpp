// Cyclic directions of a linearised model: see cyclic_directions.hpp.
#include "analyses/cyclic_directions.hpp"

#include <Eigen/SVD>

#include <cmath>

namespace mbd {

Eigen::MatrixXd null_space(const Eigen::MatrixXd& X, double tolerance) {
    if (X.rows() == 0 || X.cols() == 0) return Eigen::MatrixXd::Identity(X.cols(), X.cols());
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(X, Eigen::ComputeFullV);
    Eigen::Index rank = 0;
    for (Eigen::Index i = 0; i < svd.singularValues().size(); ++i)
        if (svd.singularValues()[i] > tolerance) ++rank;
    return svd.matrixV().rightCols(X.cols() - rank);
}

Eigen::MatrixXd orthonormal_basis(const Eigen::MatrixXd& X) {
    if (X.cols() == 0) return Eigen::MatrixXd(X.rows(), 0);
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(X, Eigen::ComputeThinU);
    return svd.matrixU().leftCols(X.cols());
}

Eigen::MatrixXd invariant_position_subspace(const Eigen::MatrixXd& A, const Eigen::MatrixXd& carried,
                                            const Eigen::MatrixXd& within, double tolerance) {
    Eigen::MatrixXd S = orthonormal_basis(within);
    while (S.cols() > 0) {
        Eigen::MatrixXd states(A.rows(), S.cols());
        states << S, carried * S;
        // what a shift along S changes: every rate, less those along the shifts themselves
        const Eigen::MatrixXd Q = orthonormal_basis(states);
        Eigen::MatrixXd changes = A * states;
        changes -= Q * (Q.transpose() * changes);
        const Eigen::MatrixXd kept = null_space(changes, tolerance);
        if (kept.cols() == S.cols()) break;
        S = S * kept;
    }
    return S;
}

Eigen::MatrixXd reduced_echelon(const Eigen::MatrixXd& S, std::vector<int>& pivots) {
    Eigen::MatrixXd R = S.transpose();  // s x kz
    pivots.clear();
    std::vector<char> used(R.cols(), 0);
    for (Eigen::Index r = 0; r < R.rows(); ++r) {
        Eigen::Index p = 0;
        double best = -1.0;
        for (Eigen::Index c = 0; c < R.cols(); ++c)
            if (!used[c] && std::abs(R(r, c)) > best) best = std::abs(R(r, c)), p = c;
        used[p] = 1;
        pivots.push_back(static_cast<int>(p));
        R.row(r) /= R(r, p);
        for (Eigen::Index o = 0; o < R.rows(); ++o)
            if (o != r) R.row(o) -= R(o, p) * R.row(r);
    }
    for (Eigen::Index r = 0; r < R.rows(); ++r) {
        for (Eigen::Index c = 0; c < R.cols(); ++c)
            if (std::abs(R(r, c)) < 1e-8) R(r, c) = 0.0;
        R(r, pivots[r]) = 1.0;
    }
    return R.transpose();
}

}  // namespace mbd
