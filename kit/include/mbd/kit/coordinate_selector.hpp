// The one choice of independent coordinates of every partitioned formulation (embedding's
// dense path, amalgamated, hamiltonian): the dense threshold complete pivoting of sdk
// partition.hpp for small systems, the sparse elimination of sparse_partition.hpp above the
// project's sparse threshold (FormulationOptions::sparse_threshold velocity coordinates, or as
// forced by linear_algebra). Both follow the pivot rule of partition.hpp; callers keep the
// re-selection rule of Sec. 6.12 (pivot ratio of J_d below reselect_ratio) unchanged.
#pragma once

#include <mbd/kit/sparse_partition.hpp>

#include <mbd/kit/formulation_options.hpp>
#include <mbd/kit/partition.hpp>

#include <Eigen/SparseCore>

#include <algorithm>
#include <vector>

namespace mbd {

// the same elements (each list has distinct entries), without sorting copies: whether a
// re-selection chose the same coordinates again
inline bool same_set(const std::vector<int>& a, const std::vector<int>& b) {
    if (a.size() != b.size()) return false;
    for (int x : a)
        if (std::find(b.begin(), b.end(), x) == b.end()) return false;
    return true;
}

class CoordinateSelector {
public:
    // for m x n Jacobians; the algebra from the options (Auto: sparse above sparse_threshold).
    // `out`: a partition to size up front, so that a dense re-selection into it allocates nothing.
    void bind(int m, int n, const FormulationOptions& options, CoordinatePartition& out) {
        sparse_ = options.algebra == LinearAlgebra::Sparse ||
                  (options.algebra == LinearAlgebra::Auto && n > options.sparse_threshold);
        reserve_partition(sparse_ ? 0 : m, sparse_ ? 0 : n, dense_, out);
        reserve_lists(m, n, out);
        const int rank = std::min(m, n);
        const int scored = sparse_ && rank <= kCompletePivotingRank ? rank : 0;  // dependent_pivot_ratio's dense J_d
        reserve_partition(scored, scored, scoring_, scratch_);
        reserve_lists(m, n, scratch_);
        row_position_.assign(m, -1);
    }
    bool sparse() const { return sparse_; }

    // the partition of J into `out` (threshold, rank_tolerance and last as in partition.hpp)
    void select(const Eigen::SparseMatrix<double>& J, double threshold, double rank_tolerance,
                const std::vector<int>& last, CoordinatePartition& out) {
        if (sparse_) {
            partition_sparse(J, threshold, rank_tolerance, last, sparse_ws_, out);
        } else {
            dense_.a = J;  // into the sized workspace
            partition_workspace_matrix(threshold, rank_tolerance, last, dense_, out);
        }
    }
    // The pivot ratio of p's J_d at a sparse J, to compare a current partition with a
    // re-selected one (Sec. 6.12). Up to kCompletePivotingRank dependent coordinates, J_d is
    // gathered densely and measured by complete pivoting (partition.hpp), the dense path's
    // measure: the sparse elimination pivots along rows in row order, which near A02's dead
    // points rates the current partition and its re-selection alike and never switches.
    // Larger J_d (where rank^3 work per check would dominate): that elimination restricted to
    // p's columns (sparse_partition.hpp).
    static constexpr int kCompletePivotingRank = 600;
    double dependent_pivot_ratio(const Eigen::SparseMatrix<double>& J, const CoordinatePartition& p,
                                 double rank_tolerance) {
        if (p.rank > kCompletePivotingRank) return mbd::dependent_pivot_ratio(J, p, rank_tolerance, sparse_ws_, scratch_);
        if (p.rank == 0) return 1.0;
        gather_dependent(J, p, scoring_.a);
        partition_workspace_matrix(1.0, 0.0, {}, scoring_, scratch_);
        return scratch_.rank < p.rank ? 0.0 : scratch_.pivot_ratio;
    }
    CoordinatePartition select(const Eigen::SparseMatrix<double>& J, double threshold, double rank_tolerance,
                               const std::vector<int>& last = {}) {
        CoordinatePartition out;
        select(J, threshold, rank_tolerance, last, out);
        return out;
    }

private:
    static void reserve_lists(int m, int n, CoordinatePartition& p) {
        p.dependent.reserve(std::min(m, n));
        p.rows.reserve(std::min(m, n));
        p.independent.reserve(n);
        p.redundant.reserve(m);
    }
    // out = J[p.rows, p.dependent], dense
    void gather_dependent(const Eigen::SparseMatrix<double>& J, const CoordinatePartition& p, Eigen::MatrixXd& out) {
        out.setZero(p.rank, p.rank);
        for (int i = 0; i < p.rank; ++i) row_position_[p.rows[i]] = i;
        for (int j = 0; j < p.rank; ++j)
            for (Eigen::SparseMatrix<double>::InnerIterator it(J, p.dependent[j]); it; ++it)
                if (row_position_[it.row()] >= 0) out(row_position_[it.row()], j) = it.value();
        for (int i = 0; i < p.rank; ++i) row_position_[p.rows[i]] = -1;
    }

    bool sparse_ = false;
    PartitionWorkspace dense_;
    SparsePartitionWorkspace sparse_ws_;
    PartitionWorkspace scoring_;     // dependent_pivot_ratio's dense J_d
    CoordinatePartition scratch_;    // dependent_pivot_ratio's elimination
    std::vector<int> row_position_;  // per row of J: its place in J_d (-1: none), between calls all -1
};

}  // namespace mbd
