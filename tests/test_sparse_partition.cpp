// The sparse coordinate partition (kit/include/mbd/kit/sparse_partition.hpp) against
// independent oracles: the numerical rank of J by SVD, J_d = J[rows, dependent] nonsingular,
// redundant rows in the span of the kept rows (least squares), the Bricard mechanism's one
// degree of freedom (its Gruebler count is 0: one of its rows is redundant), and a four-bar
// driven through its rocker's dead points, where the pivot-ratio rule of Sec. 6.12 must
// re-select with the sparse elimination as it does with the dense one.
#include "support/four_bar_dead_points.hpp"
#include "support/test_support.hpp"

#include <mbd/model_system.hpp>
#include <mbd/simulation.hpp>
#include <mbd/kit/partition.hpp>
#include <mbd/kit/velocity_transform.hpp>
#include <mbd/kit/coordinate_selector.hpp>
#include <mbd/kit/sparse_partition.hpp>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <string>

namespace {

// the numerical rank of A by SVD (relative tolerance 1e-9)
int svd_rank(const Eigen::MatrixXd& A, double* smallest_kept = nullptr) {
    if (A.size() == 0) return 0;
    const Eigen::VectorXd s = Eigen::JacobiSVD<Eigen::MatrixXd>(A).singularValues();
    int r = 0;
    while (r < s.size() && s[r] > 1e-9 * s[0]) ++r;
    if (smallest_kept) *smallest_kept = r ? s[r - 1] / s[0] : 0.0;
    return r;
}

// Every property the partition promises, checked on J with dense algebra.
void expect_valid_partition(const Eigen::MatrixXd& J, const mbd::CoordinatePartition& p) {
    const int m = static_cast<int>(J.rows()), n = static_cast<int>(J.cols());
    ASSERT_EQ(static_cast<int>(p.dependent.size()), p.rank);
    ASSERT_EQ(static_cast<int>(p.rows.size()), p.rank);
    EXPECT_EQ(p.rank + static_cast<int>(p.independent.size()), n);
    EXPECT_EQ(p.rank + static_cast<int>(p.redundant.size()), m);
    std::vector<int> columns = p.dependent;
    columns.insert(columns.end(), p.independent.begin(), p.independent.end());
    std::sort(columns.begin(), columns.end());
    for (int c = 0; c < n; ++c) EXPECT_EQ(columns[c], c) << "dependent and independent columns partition v";
    EXPECT_EQ(p.rank, svd_rank(J)) << "the rank of J";
    Eigen::MatrixXd Jd;
    mbd::gather(J, p.rows, p.dependent, Jd);
    double smallest = 0.0;
    EXPECT_EQ(svd_rank(Jd, &smallest), p.rank) << "J_d is nonsingular";
    Eigen::MatrixXd kept(p.rank, n);
    for (int i = 0; i < p.rank; ++i) kept.row(i) = J.row(p.rows[i]);
    for (int r : p.redundant) {  // row r = kept^T c for some c
        const Eigen::VectorXd row = J.row(r).transpose();
        const Eigen::VectorXd c = kept.transpose().colPivHouseholderQr().solve(row);
        EXPECT_LT((kept.transpose() * c - row).norm(), 1e-8 * std::max(1.0, row.norm())) << "redundant row " << r;
    }
}

Eigen::SparseMatrix<double> jacobian_at_assembly(mbd::ModelSystem& system) {
    mbd::State state = system.initial_state();
    system.assemble(state, true);
    mbd::ConstraintValues cv;
    system.constraints(state, cv, true);
    return cv.J;
}

TEST(SparsePartition, ValidOnBookAndBenchScenes) {
    for (const char* path : {"book/bricard.yaml", "bench/a04-bricard.yaml", "bench/a02-four-bar-2.yaml",
                             "bench/chain-50.yaml", "bench/a05-flyball.yaml", "dynamics/slider-crank.yaml"}) {
        SCOPED_TRACE(path);
        const mbd::Model model = mbd::test::load(path);
        mbd::ModelSystem system(model);
        const Eigen::SparseMatrix<double> J = jacobian_at_assembly(system);
        for (double threshold : {0.1, 1.0}) {
            const mbd::CoordinatePartition p = mbd::partition_sparse(J, threshold, 1e-10);
            expect_valid_partition(Eigen::MatrixXd(J), p);
            EXPECT_GT(p.pivot_ratio, 0.0);
        }
    }
}

// A re-selection compares the current partition with a fresh one by the pivot ratio of each
// J_d (coordinate_selector.hpp): up to 600 dependent coordinates by complete pivoting of the
// gathered J_d, which must equal the dense path's measure on the dense J (sdk
// velocity_transform.hpp); above, by the sparse elimination restricted to J_d's columns, which
// for a partition that elimination chose itself (threshold 1) must find the same pivots.
TEST(SparsePartition, CandidatesAreScoredAsTheDensePathScoresThem) {
    for (const char* path : {"bench/a02-four-bar-40.yaml", "bench/chain-50.yaml", "book/bricard.yaml", "bench/chain-500.yaml"}) {
        SCOPED_TRACE(path);
        const mbd::Model model = mbd::test::load(path);
        mbd::ModelSystem system(model);
        const Eigen::SparseMatrix<double> J = jacobian_at_assembly(system);
        mbd::FormulationOptions options;
        options.algebra = mbd::LinearAlgebra::Sparse;
        mbd::CoordinateSelector selector;
        mbd::CoordinatePartition fresh;
        selector.bind(static_cast<int>(J.rows()), static_cast<int>(J.cols()), options, fresh);
        mbd::SparsePartitionWorkspace ws;
        mbd::CoordinatePartition scratch;
        for (double threshold : {0.1, 1.0}) {
            const mbd::CoordinatePartition p = mbd::partition_sparse(J, threshold, 1e-10);
            const double scored = selector.dependent_pivot_ratio(J, p, 1e-10);
            const double restricted = mbd::dependent_pivot_ratio(J, p, 1e-10, ws, scratch);
            EXPECT_GT(scored, 0.0);
            if (threshold == 1.0) EXPECT_NEAR(restricted, p.pivot_ratio, 1e-14 * p.pivot_ratio);
            if (p.rank <= mbd::CoordinateSelector::kCompletePivotingRank) {
                mbd::VelocityTransformWorkspace dense;
                EXPECT_NEAR(scored, mbd::dependent_pivot_ratio(Eigen::MatrixXd(J), p, dense), 1e-14 * scored);
            } else {
                EXPECT_EQ(scored, restricted);
            }
        }
    }
}

TEST(SparsePartition, BricardHasOneDegreeOfFreedomAndARedundantRow) {
    for (const char* path : {"book/bricard.yaml", "bench/a04-bricard.yaml"}) {
        SCOPED_TRACE(path);
        const mbd::Model model = mbd::test::load(path);
        mbd::ModelSystem system(model);
        const Eigen::SparseMatrix<double> J = jacobian_at_assembly(system);
        const mbd::CoordinatePartition p = mbd::partition_sparse(J);
        // the Bricard linkage moves with one degree of freedom although the mobility count is 0
        // (a driver takes that one degree of freedom)
        EXPECT_EQ(static_cast<int>(p.independent.size()), 1 - system.driver_count());
        EXPECT_GE(p.redundant.size(), 1u);
        expect_valid_partition(Eigen::MatrixXd(J), p);
    }
}

TEST(SparsePartition, PreferredColumnsStayIndependentWhenTheyCan) {
    const mbd::Model model = mbd::test::load("bench/chain-50.yaml");
    mbd::ModelSystem system(model);
    const Eigen::SparseMatrix<double> J = jacobian_at_assembly(system);
    const mbd::CoordinatePartition first = mbd::partition_sparse(J);
    // asking for the first partition's dependent columns to come last makes other columns dependent
    const mbd::CoordinatePartition other = mbd::partition_sparse(J, 1e-3, 1e-10, first.dependent);
    expect_valid_partition(Eigen::MatrixXd(J), other);
    int shared = 0;
    for (int c : other.dependent) shared += std::count(first.dependent.begin(), first.dependent.end(), c);
    EXPECT_LT(shared, first.rank);
}

// The crank-rocker four-bar through its dead points (support/four_bar_dead_points.hpp), where
// rocker.angle cannot stay independent.
const std::string kFourBar = mbd::test::four_bar_dead_points("formulation: {type: augmented}");

// Along the augmented formulation's trajectory (the oracle), the rule of Sec. 6.12 (re-select
// when J_d's pivot ratio falls below 0.05, keep the fresh partition if its ratio is better)
// with partition `select`; returns the number of re-selections and the least pivot ratio met
// after the check.
template <class Select>
int follow_dead_points(Select select, double* least_ratio) {
    const mbd::Model model = mbd::test::scene(kFourBar, "four-bar.yaml");
    const mbd::SimulationSettings s = mbd::test::adaptive_run("augmented", "dopri5", 1e-10, 3.0, 0.002);
    std::vector<mbd::State> states;
    mbd::simulate(model, mbd::test::shared_registry(), s, [&](const mbd::SimulationSample& sample) {
        states.push_back(sample.state);
        return true;
    });
    mbd::ModelSystem system(model);
    mbd::ConstraintValues cv;
    mbd::VelocityTransformWorkspace ws;
    system.constraints(states.front(), cv, true);
    const std::vector<int> rocker_last = {8};  // rocker.angle (body 2, component 2) independent
    mbd::CoordinatePartition p = select(cv.J, 1e-3, rocker_last);
    EXPECT_EQ(p.independent, rocker_last);
    int switches = 0;
    *least_ratio = 1.0;
    for (const mbd::State& state : states) {
        system.constraints(state, cv, true);
        const Eigen::MatrixXd J(cv.J);
        double ratio = mbd::dependent_pivot_ratio(J, p, ws);
        if (ratio < 0.05) {
            const mbd::CoordinatePartition fresh = select(cv.J, 1.0, {});
            expect_valid_partition(J, fresh);
            if (fresh.dependent != p.dependent && mbd::dependent_pivot_ratio(J, fresh, ws) > ratio) {
                p = fresh;
                ++switches;
                ratio = mbd::dependent_pivot_ratio(J, p, ws);
            }
        }
        *least_ratio = std::min(*least_ratio, ratio);
    }
    return switches;
}

TEST(SparsePartition, ReselectsThroughTheFourBarDeadPointsAsTheDenseOneDoes) {
    double sparse_least = 0.0, dense_least = 0.0;
    const int sparse_switches = follow_dead_points(
        [](const Eigen::SparseMatrix<double>& J, double threshold, const std::vector<int>& last) {
            return mbd::partition_sparse(J, threshold, 1e-10, last);
        },
        &sparse_least);
    const int dense_switches = follow_dead_points(
        [](const Eigen::SparseMatrix<double>& J, double threshold, const std::vector<int>& last) {
            return mbd::partition_coordinates(Eigen::MatrixXd(J), threshold, 1e-10, last);
        },
        &dense_least);
    std::printf("dead points: sparse %d re-selections (least pivot ratio %.3g), dense %d (%.3g)\n", sparse_switches,
                sparse_least, dense_switches, dense_least);
    EXPECT_GE(dense_switches, 1);
    EXPECT_GE(sparse_switches, 1);
    // at 500 samples a second the ratio can fall below the threshold between two checks, not to 0
    EXPECT_GT(sparse_least, 1e-3);
    EXPECT_GT(dense_least, 1e-3);
}

}  // namespace

namespace {

// The elimination's work is its fill: the entries of the pivot rows it keeps. Retiring
// columns (the initial selection's threshold), each pivot row of a chain in scene order holds
// a bounded number of entries whatever the length, so the selection costs O(n): the fill per
// pivot of a 500-link chain is that of a 50-link one.
TEST(SparsePartition, FillPerPivotDoesNotGrowWithTheChain) {
    double per_pivot[2] = {0.0, 0.0};
    int slot = 0;
    for (const char* path : {"bench/chain-50.yaml", "bench/chain-500.yaml"}) {
        const mbd::Model model = mbd::test::load(path);
        mbd::ModelSystem system(model);
        const Eigen::SparseMatrix<double> J = jacobian_at_assembly(system);
        mbd::SparsePartitionWorkspace ws;
        mbd::CoordinatePartition p;
        mbd::partition_sparse(J, 0.1, 1e-10, {}, ws, p);  // the initial selection's threshold
        ASSERT_EQ(p.rank, J.rows()) << path << ": a chain has no redundant rows";
        if (slot == 0) expect_valid_partition(Eigen::MatrixXd(J), p);  // a dense SVD: the short chain only
        per_pivot[slot] = static_cast<double>(ws.u_column.size()) / p.rank;
        ++slot;
    }
    std::printf("pivot-row entries per pivot: chain-50 %.2f, chain-500 %.2f\n", per_pivot[0], per_pivot[1]);
    EXPECT_LT(per_pivot[1], 1.05 * per_pivot[0]);
    EXPECT_LT(per_pivot[1], 10.0);
}

}  // namespace
