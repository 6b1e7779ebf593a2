#include <mbd/newton.hpp>

#include <cmath>

namespace mbd {

NewtonResult newton_raphson(NonlinearEquations& equations, Eigen::VectorXd& x, const NewtonOptions& options,
                            bool keep_trace) {
    NewtonResult result;
    Eigen::VectorXd C;
    Eigen::SparseMatrix<double> J;
    MinNormSolver solver(options.algebra);
    auto worst = [&](const Eigen::VectorXd& c, int& row) {
        double value = 0.0;
        row = -1;
        for (int k = 0; k < c.size(); ++k)
            if (!(std::abs(c[k]) <= value)) {  // also catches NaN
                value = std::abs(c[k]);
                row = k;
            }
        return value;
    };

    equations.evaluate(x, C, J);
    result.residual = worst(C, result.worst_row);
    // book Eqs. 3.115-3.117: C_q dq = -C, q <- q + dq, until max |C| is below the tolerance
    while (result.iterations < options.max_iterations && std::isfinite(result.residual) &&
           result.residual > options.tolerance) {
        if (!solver.factor(J)) break;
        const Eigen::VectorXd dx = -solver.solve(C);
        if (keep_trace) result.trace.push_back({x, C, Eigen::MatrixXd(J), dx});
        equations.advance(x, dx);
        ++result.iterations;
        equations.evaluate(x, C, J);
        result.residual = worst(C, result.worst_row);
    }
    result.converged = std::isfinite(result.residual) && result.residual <= options.tolerance;
    return result;
}

}  // namespace mbd
