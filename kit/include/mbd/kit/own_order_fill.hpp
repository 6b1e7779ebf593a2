// The entries of the Cholesky factor L (diagonal included) of the pattern of K + K^T in K's own
// order, without reordering: the fill that an elimination in that order makes when it pivots on
// the diagonal (fixed_pattern_lu.hpp compares it with AMD's before it factors K in its own
// order, so that an order that would fill a dense block is never tried). Work and memory
// O(nnz(K) + the count), from the elimination tree (Eigen's symbolic Cholesky analysis).
#pragma once

#include <Eigen/SparseCore>

namespace mbd {

long own_order_cholesky_entries(const Eigen::SparseMatrix<double>& K);

// The sparse factorizations (fixed_pattern_lu.hpp, sparse_gram.cpp) order a matrix by AMD, and
// from kCompareOrderingsFrom rows on keep the matrix's own order (scene order: the bodies, the
// joints) when it fills at most kOwnOrderSlack times as much. AMD's fill is near the least, but
// on a long chain it eliminates far-apart parts of the mechanism in turn, so each column's update
// reads factor columns stored far away; once the factors outgrow the caches (not below a few
// thousand rows) that costs more than a tenth more entries read in order.
constexpr int kCompareOrderingsFrom = 5000;
constexpr double kOwnOrderSlack = 1.1;

}  // namespace mbd
