#include <mbd/linear_algebra.hpp>

#include <mbd/sdk/params.hpp>

#include <Eigen/CholmodSupport>
#include <Eigen/Dense>

namespace mbd {

LinearAlgebra parse_linear_algebra(const std::string& name) {
    if (name == "auto") return LinearAlgebra::Auto;
    if (name == "dense") return LinearAlgebra::Dense;
    if (name == "sparse") return LinearAlgebra::Sparse;
    throw InputError("", "unknown linear algebra '" + name + "'; use auto, dense or sparse");
}

const char* to_string(LinearAlgebra algebra) {
    switch (algebra) {
        case LinearAlgebra::Auto: return "auto";
        case LinearAlgebra::Dense: return "dense";
        case LinearAlgebra::Sparse: return "sparse";
    }
    return "auto";
}

struct MinNormSolver::Impl {
    // dense path
    Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod;
    // sparse path: (J J^T + delta I) y = b, x = J^T y, with iterative refinement
    Eigen::SparseMatrix<double> J;
    Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>> cholmod;
};

MinNormSolver::MinNormSolver(LinearAlgebra algebra) : requested_(algebra), impl_(std::make_unique<Impl>()) {}
MinNormSolver::~MinNormSolver() = default;

bool MinNormSolver::factor(const Eigen::SparseMatrix<double>& J) {
    used_ = requested_;
    if (used_ == LinearAlgebra::Auto) used_ = J.cols() > kDefaultSparseThreshold ? LinearAlgebra::Sparse : LinearAlgebra::Dense;
    if (used_ == LinearAlgebra::Dense) {
        impl_->cod.compute(Eigen::MatrixXd(J));
        return true;
    }
    impl_->J = J;
    Eigen::SparseMatrix<double> A = J * Eigen::SparseMatrix<double>(J.transpose());
    double max_diagonal = 0.0;
    for (int k = 0; k < A.rows(); ++k) max_diagonal = std::max(max_diagonal, A.coeff(k, k));
    // a tiny regularisation keeps consistent redundant rows solvable (damped least squares)
    const double delta = 1e-12 * std::max(max_diagonal, 1.0);
    Eigen::SparseMatrix<double> I(A.rows(), A.rows());
    I.setIdentity();
    A += delta * I;
    impl_->cholmod.compute(A);
    return impl_->cholmod.info() == Eigen::Success;
}

Eigen::VectorXd MinNormSolver::solve(const Eigen::VectorXd& b) const {
    if (used_ == LinearAlgebra::Dense) return impl_->cod.solve(b);
    const auto& J = impl_->J;
    Eigen::VectorXd x = J.transpose() * impl_->cholmod.solve(b);
    for (int refine = 0; refine < 2; ++refine) {
        const Eigen::VectorXd r = b - J * x;
        x += J.transpose() * impl_->cholmod.solve(r);
    }
    return x;
}

}  // namespace mbd
