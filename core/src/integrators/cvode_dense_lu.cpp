// Eigen's partial-pivoting LU behind the SUNLinearSolver interface (cvode_dense_lu.hpp).
#include "cvode_dense_lu.hpp"

#include <nvector/nvector_serial.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <Eigen/LU>

#include <cmath>
#include <new>

namespace mbd::integrators {
namespace {

// Everything sized once, at creation: setup and solve allocate nothing.
struct DenseLu {
    explicit DenseLu(int n) : lu(n), work(n) {}
    Eigen::PartialPivLU<Eigen::MatrixXd> lu;
    Eigen::VectorXd work;
    sunindextype last_flag = 0;  // 0, or the 1-based column of a zero pivot
};

DenseLu& content(SUNLinearSolver S) { return *static_cast<DenseLu*>(S->content); }

Eigen::Map<const Eigen::MatrixXd> dense(SUNMatrix A) {
    return {SUNDenseMatrix_Data(A), static_cast<Eigen::Index>(SUNDenseMatrix_Rows(A)),
            static_cast<Eigen::Index>(SUNDenseMatrix_Columns(A))};
}

Eigen::Map<Eigen::VectorXd> vector(N_Vector v) {
    return {N_VGetArrayPointer(v), static_cast<Eigen::Index>(N_VGetLength(v))};
}

SUNLinearSolver_Type get_type(SUNLinearSolver) { return SUNLINEARSOLVER_DIRECT; }
SUNLinearSolver_ID get_id(SUNLinearSolver) { return SUNLINEARSOLVER_CUSTOM; }
int initialize(SUNLinearSolver S) {
    content(S).last_flag = 0;
    return SUNLS_SUCCESS;
}

int setup(SUNLinearSolver S, SUNMatrix A) {
    DenseLu& c = content(S);
    if (SUNMatGetID(A) != SUNMATRIX_DENSE || SUNDenseMatrix_Rows(A) != c.work.size() ||
        SUNDenseMatrix_Columns(A) != c.work.size())
        return SUNLS_ILL_INPUT;
    c.lu.compute(dense(A));
    c.last_flag = 0;
    const auto pivots = c.lu.matrixLU().diagonal();
    for (Eigen::Index k = 0; k < pivots.size(); ++k)
        if (pivots[k] == 0.0 || !std::isfinite(pivots[k])) {
            c.last_flag = k + 1;
            return SUNLS_LUFACT_FAIL;  // > 0: recoverable
        }
    return SUNLS_SUCCESS;
}

int solve(SUNLinearSolver S, SUNMatrix, N_Vector x, N_Vector b, realtype) {
    DenseLu& c = content(S);
    c.work = vector(b);  // x and b may be the same vector
    vector(x) = c.lu.solve(c.work);
    return SUNLS_SUCCESS;
}

sunindextype last_flag(SUNLinearSolver S) { return content(S).last_flag; }

int space(SUNLinearSolver S, long* real_words, long* integer_words) {
    const long n = static_cast<long>(content(S).work.size());
    *real_words = n * n + n;
    *integer_words = n;
    return SUNLS_SUCCESS;
}

int free_solver(SUNLinearSolver S) {
    if (!S) return SUNLS_SUCCESS;
    delete static_cast<DenseLu*>(S->content);
    S->content = nullptr;
    SUNLinSolFreeEmpty(S);
    return SUNLS_SUCCESS;
}

}  // namespace

SUNLinearSolver make_dense_lu_solver(int n, SUNContext context) {
    SUNLinearSolver S = SUNLinSolNewEmpty(context);
    if (!S) return nullptr;
    S->content = new (std::nothrow) DenseLu(n);
    if (!S->content) {
        SUNLinSolFreeEmpty(S);
        return nullptr;
    }
    S->ops->gettype = get_type;
    S->ops->getid = get_id;
    S->ops->initialize = initialize;
    S->ops->setup = setup;
    S->ops->solve = solve;
    S->ops->lastflag = last_flag;
    S->ops->space = space;
    S->ops->free = free_solver;
    return S;
}

}  // namespace mbd::integrators
