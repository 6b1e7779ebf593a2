// Minimum-norm solutions of J x = b for constraint Jacobians, dense (Eigen
// complete orthogonal decomposition, robust to rank deficiency) or sparse
// (SuiteSparse CHOLMOD on J J^T, with a tiny regularisation so that consistent
// redundant constraints still solve). The switch size is LinearAlgebra::Auto's
// threshold on the number of velocity coordinates.
#pragma once

#include <Eigen/Core>
#include <Eigen/Sparse>

#include <memory>
#include <string>

namespace mbd {

enum class LinearAlgebra { Auto, Dense, Sparse };

LinearAlgebra parse_linear_algebra(const std::string& name);  // "auto" | "dense" | "sparse"
const char* to_string(LinearAlgebra algebra);

// Number of velocity coordinates above which Auto picks the sparse path.
constexpr int kSparseThreshold = 300;

class MinNormSolver {
public:
    explicit MinNormSolver(LinearAlgebra algebra = LinearAlgebra::Auto);
    ~MinNormSolver();

    // Factor J (rows x cols). Returns false if the factorization failed.
    bool factor(const Eigen::SparseMatrix<double>& J);
    // x = J^+ b (least-squares, minimum norm).
    Eigen::VectorXd solve(const Eigen::VectorXd& b) const;
    // Which path the last factor() used.
    LinearAlgebra used() const { return used_; }

private:
    struct Impl;
    LinearAlgebra requested_;
    LinearAlgebra used_ = LinearAlgebra::Dense;
    std::unique_ptr<Impl> impl_;
};

}  // namespace mbd
