// Coordinate partitioning of a SPARSE constraint Jacobian (Shabana, Computational Dynamics,
// Sec. 6.5 "Identification of the system degrees of freedom"; Sec. 6.12): the same result
// type as the dense elimination of kit partition.hpp (dependent pivot columns, independent
// columns, kept and redundant rows, pivot ratio).
//
// Algebra: Gaussian elimination by rows (row r of J reduced by the pivot rows before it, in
// pivot order, on a sparse accumulator) with threshold partial pivoting along the row, where
// the dense code pivots completely over the whole remaining matrix (whose global search is
// O(n^2)). The pivot rule is the dense one restricted to the row: the largest remaining entry
// |a|max of the reduced row is found; the row's columns are scanned in preference order
// (columns in `last` after every other one, then ascending) and the first whose entry is at
// least threshold * |a|max is the pivot. threshold = 1 takes the row's largest entry (the
// choice of a re-selection). A row whose reduced entries are all below rank_tolerance times
// the largest entry of J is redundant (book L8314), as in the dense code.
//
// Cost: in absolute coordinates every dependent velocity depends on the independent ones of
// all bodies before it (B is dense), so carried along, the independent columns fill every
// reduced row (O(n k) work on a chain). A column is therefore RETIRED once the last row of J
// that holds it has been reduced without choosing it: it stays independent, and its fill is
// dropped, which changes no other entry (a pivot row's multiplier reads only its pivot
// column). The work is then the fill among the columns still in play: O(n) on chains, trees
// and local loops in scene order. Retiring can hide a row that still holds only retired
// columns and would look redundant; when a row is found redundant after something was
// dropped, the partition is made again without retiring (exactly, at O(n k)). A re-selection
// (threshold 1) does not retire either: a retired column can be the best pivot there (the
// 40 four-bars of scenes/extreme/a02-four-bar-40-singular need it); re-selections are rare.
#pragma once

#include <mbd/kit/partition.hpp>

#include <Eigen/SparseCore>

#include <vector>

namespace mbd {

// Scratch of the sparse elimination, reused from call to call.
struct SparsePartitionWorkspace {
    Eigen::SparseMatrix<double, Eigen::RowMajor> rows;  // J by rows
    std::vector<int> pattern_outer, pattern_inner;      // J's pattern when `rows` was built
    std::vector<int> slot;                              // per entry of J: its place in rows' values
    Eigen::VectorXd work;                               // the sparse accumulator (dense, zero between rows)
    std::vector<int> pattern;                           // the columns present in `work`
    std::vector<char> present, late, queued;
    std::vector<int> step_of_column;                    // -1: not a pivot column
    std::vector<int> heap;                              // pivot steps still to apply to the current row
    std::vector<int> u_start;                           // the pivot rows (U): entries of step s at [u_start[s], u_start[s+1])
    std::vector<int> u_column;
    std::vector<double> u_value, pivot;
    std::vector<int> last_row;                          // the last row of J holding each column
    std::vector<char> allowed;                          // per column: may pivot (empty: every column)
    int current_row = 0;
    bool dropped = false;                               // fill of a retired column was dropped
    bool retired(int c) const { return step_of_column[c] < 0 && last_row[c] < current_row; }
    bool excluded(int c) const { return !allowed.empty() && !allowed[c]; }
};

// The partition of J (m x n) into `out`; `last` as in partition.hpp.
void partition_sparse(const Eigen::SparseMatrix<double>& J, double threshold, double rank_tolerance,
                      const std::vector<int>& last, SparsePartitionWorkspace& ws, CoordinatePartition& out);

// The pivot ratio of partition p's J_d at J, measured as a re-selection (threshold 1) measures
// its own: the elimination above with pivots only among p's dependent columns (the others are
// dropped, as retired ones: their fill changes no other entry). So a current partition and a
// re-selected one compare like with like, and nothing is factored or ordered for either (a
// sparse LU's pivots follow its own ordering, and ordering a new J_d allocates). 0 when J_d
// has lost rank. `scratch` receives that elimination's partition.
double dependent_pivot_ratio(const Eigen::SparseMatrix<double>& J, const CoordinatePartition& p, double rank_tolerance,
                             SparsePartitionWorkspace& ws, CoordinatePartition& scratch);

// The same, allocating its own scratch.
CoordinatePartition partition_sparse(const Eigen::SparseMatrix<double>& J, double threshold = 0.1,
                                     double rank_tolerance = 1e-10, const std::vector<int>& last = {});

}  // namespace mbd
