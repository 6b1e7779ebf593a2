// The entries of the Cholesky factor L (diagonal included) of the pattern of K + K^T in K's own
// order, without reordering: the fill that an elimination in that order makes when it pivots on
// the diagonal (fixed_pattern_lu.hpp compares it with AMD's before it factors K in its own
// order, so that an order that would fill a dense block is never tried). Work and memory
// O(nnz(K) + the count), from the elimination tree (Eigen's symbolic Cholesky analysis).
#pragma once

#include <Eigen/SparseCore>

namespace mbd {

long own_order_cholesky_entries(const Eigen::SparseMatrix<double>& K);

}  // namespace mbd
