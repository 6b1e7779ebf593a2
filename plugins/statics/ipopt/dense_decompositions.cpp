#include "dense_decompositions.hpp"

#include <Eigen/Dense>

#include <algorithm>

namespace mbd::ipopt_plugin {
namespace {

int numerical_rank(const Eigen::VectorXd& singular_values, double relative_tolerance) {
    int rank = 0;
    for (Eigen::Index i = 0; i < singular_values.size(); ++i)
        if (singular_values[i] > relative_tolerance * std::max(1.0, singular_values[0])) ++rank;
    return rank;
}

}  // namespace

SingularValueDecomposition singular_value_decomposition(const Eigen::MatrixXd& A, bool full_u,
                                                        double relative_tolerance) {
    const Eigen::BDCSVD<Eigen::MatrixXd> svd(A, (full_u ? Eigen::ComputeFullU : Eigen::ComputeThinU) |
                                                    Eigen::ComputeFullV);
    SingularValueDecomposition out;
    out.values = svd.singularValues();
    out.U = svd.matrixU();
    out.V = svd.matrixV();
    out.rank = numerical_rank(out.values, relative_tolerance);
    return out;
}

Eigen::MatrixXd null_space(const Eigen::MatrixXd& A, int n, int& rank, double relative_tolerance) {
    if (A.rows() == 0) {
        rank = 0;
        return Eigen::MatrixXd::Identity(n, n);
    }
    const Eigen::BDCSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeFullV);
    rank = numerical_rank(svd.singularValues(), relative_tolerance);
    return svd.matrixV().rightCols(n - rank);
}

bool symmetric_eigen(const Eigen::MatrixXd& H, Eigen::VectorXd& values, Eigen::MatrixXd* vectors) {
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (H + H.transpose()),
                                                             vectors ? Eigen::ComputeEigenvectors : Eigen::EigenvaluesOnly);
    if (eig.info() != Eigen::Success) return false;
    values = eig.eigenvalues();
    if (vectors) *vectors = eig.eigenvectors();
    return true;
}

}  // namespace mbd::ipopt_plugin
