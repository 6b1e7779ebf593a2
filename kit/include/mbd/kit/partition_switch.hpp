// The sparse path's move to a re-selected coordinate partition (book Sec. 6.12). Near a
// singular position a mechanism switches between a few partitions and back (IFToMM A02's
// four-bars at every dead point), and ordering a new J_d (KLU's analysis) allocates; so the
// transform of the partition left behind is kept, and a switch back to it swaps it in: each
// distinct J_d is ordered once.
#pragma once

#include <mbd/kit/sparse_velocity_transform.hpp>

#include <mbd/kit/partition.hpp>

#include <Eigen/SparseCore>

#include <utility>

namespace mbd {

class PartitionSwitch {
public:
    // forget the kept partition (a new selection from scratch)
    void reset() { kept_valid_ = false; }

    // `part` and its `transform` become `fresh` (a partition of J); the ones left are kept
    void to(const Eigen::SparseMatrix<double>& J, const CoordinatePartition& fresh, CoordinatePartition& part,
            SparseVelocityTransform& transform) {
        const bool back = kept_valid_ && kept_.same_dependent_columns(fresh);
        transform.swap(kept_);  // the current partition's transform is kept for a switch back
        std::swap(part, kept_part_);
        if (!back) {
            part = fresh;
            transform.select(J, part);
        }
        kept_valid_ = true;
        transform.rebind(part);
        kept_.rebind(kept_part_);
    }

private:
    SparseVelocityTransform kept_;
    CoordinatePartition kept_part_;
    bool kept_valid_ = false;
};

}  // namespace mbd
