// The one choice of independent coordinates of every partitioned formulation (embedding's
// dense path, amalgamated, hamiltonian): the dense threshold complete pivoting of sdk
// partition.hpp for small systems, the sparse elimination of sparse_partition.hpp above the
// project's sparse threshold (FormulationOptions::sparse_threshold velocity coordinates, or as
// forced by linear_algebra). Both follow the pivot rule of partition.hpp; callers keep the
// re-selection rule of Sec. 6.12 (pivot ratio of J_d below reselect_ratio) unchanged.
#pragma once

#include "sparse_partition.hpp"

#include <mbd/sdk/formulation_options.hpp>
#include <mbd/sdk/partition.hpp>

#include <Eigen/SparseCore>

#include <algorithm>
#include <vector>

namespace mbd {

class CoordinateSelector {
public:
    // for m x n Jacobians; the algebra from the options (Auto: sparse above sparse_threshold).
    // `out`: a partition to size up front, so that a dense re-selection into it allocates nothing.
    void bind(int m, int n, const FormulationOptions& options, CoordinatePartition& out) {
        sparse_ = options.algebra == LinearAlgebra::Sparse ||
                  (options.algebra == LinearAlgebra::Auto && n > options.sparse_threshold);
        reserve_partition(sparse_ ? 0 : m, sparse_ ? 0 : n, dense_, out);
        out.dependent.reserve(std::min(m, n));
        out.rows.reserve(std::min(m, n));
        out.independent.reserve(n);
        out.redundant.reserve(m);
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
    CoordinatePartition select(const Eigen::SparseMatrix<double>& J, double threshold, double rank_tolerance,
                               const std::vector<int>& last = {}) {
        CoordinatePartition out;
        select(J, threshold, rank_tolerance, last, out);
        return out;
    }

private:
    bool sparse_ = false;
    PartitionWorkspace dense_;
    SparsePartitionWorkspace sparse_ws_;
};

}  // namespace mbd
