// The dense direct linear solver of the cvode integrator: a SUNDIALS SUNLinearSolver (the
// generic interface of sundials_linearsolver.h) that factors CVODE's Newton matrix
// I - gamma J (a SUNDenseMatrix) with Eigen's partial-pivoting LU. It replaces
// SUNLinSol_Dense, whose unblocked column loops took 600 000 instructions per factorization
// of the 52 x 52 flyball matrix and 70 000 per solve (callgrind, docs/integrators.md "cvode").
#pragma once

#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>

namespace mbd::integrators {

// A solver for n x n dense matrices; SUNLinSolFree frees it. Null if it cannot be allocated.
// A factorization with a zero or non-finite pivot is the recoverable SUNLS_LUFACT_FAIL
// (CVODE then retries with a smaller step), as for SUNLinSol_Dense.
SUNLinearSolver make_dense_lu_solver(int n, SUNContext context);

}  // namespace mbd::integrators
