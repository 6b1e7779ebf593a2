// Newton-Raphson for nonlinear constraint equations C(x) = 0 (book Eqs.
// 3.111-3.117): J dx = -C with minimum-norm steps, so under-determined systems
// (assembly of a mechanism with free degrees of freedom) and consistent
// redundant constraints solve too.
#pragma once

#include <mbd/linear_algebra.hpp>

#include <Eigen/Core>
#include <Eigen/Sparse>

#include <functional>
#include <vector>

namespace mbd {

class NonlinearEquations {
public:
    virtual ~NonlinearEquations() = default;
    virtual int equations() const = 0;
    virtual int unknowns() const = 0;  // size of the increment dx
    virtual void evaluate(const Eigen::VectorXd& x, Eigen::VectorXd& C, Eigen::SparseMatrix<double>& J) = 0;
    // x <- x (+) dx; the default is a plain sum.
    virtual void advance(Eigen::VectorXd& x, const Eigen::VectorXd& dx) const { x += dx; }
};

struct NewtonOptions {
    double tolerance = 1e-10;  // on max |C| (and on max |dx| for the last step)
    int max_iterations = 50;
    LinearAlgebra algebra = LinearAlgebra::Auto;
};

struct NewtonIteration {
    Eigen::VectorXd x;         // before the step
    Eigen::VectorXd C;
    Eigen::MatrixXd J;         // dense copy, only filled when tracing
    Eigen::VectorXd dx;
};

struct NewtonResult {
    bool converged = false;
    int iterations = 0;
    double residual = 0.0;     // max |C| at the end
    int worst_row = -1;        // row with the largest |C| at the end
    std::vector<NewtonIteration> trace;  // filled when options ask for it
};

NewtonResult newton_raphson(NonlinearEquations& equations, Eigen::VectorXd& x,
                            const NewtonOptions& options, bool keep_trace = false);

}  // namespace mbd
