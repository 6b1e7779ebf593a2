// The dense decompositions of the statics and inverse-dynamics plugin (null spaces of
// constraint Jacobians, eigenvalues of the tangent stiffness), instantiated once in
// dense_decompositions.cpp: Eigen's SVD and symmetric eigensolver templates are costly to
// compile, and each file that used them compiled its own copy.
#pragma once

#include <Eigen/Core>

namespace mbd::ipopt_plugin {

// A = U diag(values) V^T (full U when full_u, else thin; full V), with the numerical rank:
// the singular values above relative_tolerance * max(1, largest).
struct SingularValueDecomposition {
    Eigen::VectorXd values;
    Eigen::MatrixXd U, V;
    int rank = 0;
};
SingularValueDecomposition singular_value_decomposition(const Eigen::MatrixXd& A, bool full_u,
                                                        double relative_tolerance);

// An orthonormal basis of the null space of A (rows x n; the identity when A has no rows),
// and the rank of A (singular values above relative_tolerance * max(1, largest)).
Eigen::MatrixXd null_space(const Eigen::MatrixXd& A, int n, int& rank, double relative_tolerance);

// The eigenvalues (ascending) and eigenvectors of the symmetric part of H; false if the
// eigensolver failed.
bool symmetric_eigen(const Eigen::MatrixXd& H, Eigen::VectorXd& values, Eigen::MatrixXd* vectors = nullptr);

}  // namespace mbd::ipopt_plugin
