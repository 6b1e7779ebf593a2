// Minimum-norm solutions of J x = b for constraint Jacobians, dense (Eigen
// complete orthogonal decomposition, robust to rank deficiency) or sparse
// (SuiteSparse CHOLMOD on J J^T, with a tiny regularisation so that consistent
// redundant constraints still solve). Auto switches at kDefaultSparseThreshold velocity
// coordinates, the formulations' default (kit formulation_options.hpp).
#pragma once

#include <mbd/kit/formulation_options.hpp>

#include <Eigen/Core>
#include <Eigen/Sparse>

#include <memory>
#include <string>

namespace mbd {

LinearAlgebra parse_linear_algebra(const std::string& name);  // "auto" | "dense" | "sparse"
const char* to_string(LinearAlgebra algebra);

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
