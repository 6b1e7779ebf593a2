// The velocity transformation of a coordinate partition (book Sec. 6.5, Eqs. 6.80-6.94, 6.169;
// kit velocity_transform.hpp builds the same quantities densely) applied through a sparse LU of
// J_d = J[rows, dependent], never forming B. In absolute coordinates B (n_v x k) is dense: every
// dependent velocity of a chain depends on the independent velocities of all bodies before it,
// so B, M B and B^T M B cost O(n_v k) = O(n^2) on a chain, while J_d is as sparse as J.
//   v = B v_i + c:  v_i given, J_d v_d = -(J_i v_i + C_t) on the kept rows      (Eq. 6.169)
//   B^T x        :  x_i - J_i^T mu, J_d^T mu = x_d     (B_i = I, B_d = -J_d^-1 J_i, Eq. 6.85)
// J_d keeps its pattern until the partition is selected again: KLU orders it once per
// partition and then refactors it in place with the pivots of its last pivoting
// factorization (no allocation), pivoting again when those pivots no longer fit.
#pragma once

#include <mbd/kit/fixed_pattern_lu.hpp>

#include <mbd/kit/partition.hpp>
#include <mbd/kit/system.hpp>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <vector>

namespace mbd {

class SparseVelocityTransform {
public:
    SparseVelocityTransform() : lu_(true) {}

    // a new partition p of J (m x n): J_d's pattern and where J's entries land in it
    void select(const Eigen::SparseMatrix<double>& J, const CoordinatePartition& p);
    // J_d's values from J (J's fixed pattern) and its LU; false when J_d is singular
    bool factor(const Eigen::SparseMatrix<double>& J);
    // smallest / largest pivot of the last factor() (partial pivoting of the row-scaled J_d):
    // the re-selection measure of Sec. 6.12 on the sparse path; 0 when singular
    double pivot_ratio() { return lu_.pivot_ratio(); }
    // pivot_ratio() over its value at the first factor() after select(): partial pivoting keeps
    // the rows' geometric scale in the pivots (0.25 on IFToMM A02's four-bars, where complete
    // pivoting gives 1), so the re-selection test of Sec. 6.12 (below reselect_ratio) is applied
    // to the ratio relative to the one the partition was chosen at
    double relative_pivot_ratio() { return reference_ratio_ > 0.0 ? lu_.pivot_ratio() / reference_ratio_ : 0.0; }

    // exchanges everything with `other` (no allocation: the orderings and factors move); then
    // rebind() each to the partition it was selected for, wherever that now lives
    void swap(SparseVelocityTransform& other);
    void rebind(const CoordinatePartition& p) { p_ = &p; }

    // whether partition `other` has the selected one's dependent columns and dropped rows (in
    // any order): the same J_d up to permutations
    bool same_dependent_columns(const CoordinatePartition& other);

    // after factor(): v from v_i (Eq. 6.169); v has size n
    void velocities(const Eigen::SparseMatrix<double>& J, const Eigen::VectorXd& C_t, const Eigen::VectorXd& vi,
                    Eigen::VectorXd& v);
    // after factor(): out = B^T x (size k)
    void transpose_times(const Eigen::SparseMatrix<double>& J, const Eigen::VectorXd& x, Eigen::VectorXd& out);
    // after factor(): mu (size m) solving J_d^T mu = x_d on the kept rows, 0 on the dropped ones
    void dependent_multipliers(const Eigen::VectorXd& x, Eigen::VectorXd& mu);
    // after factor(): x_d solving J_d x_d = b[rows] (b of size m), scattered into dv (size n,
    // zero at the independent components)
    bool solve_dependent(const Eigen::VectorXd& b, Eigen::VectorXd& dv);

private:
    const CoordinatePartition* p_ = nullptr;
    Eigen::SparseMatrix<double> Jd_;
    std::vector<int> slot_;  // per entry of J (in J's storage order): its place in Jd_'s values, or -1
    FixedPatternLU lu_;
    bool pivoted_ = false;
    double pivoted_ratio_ = 0.0;  // pivot ratio of the last pivoting factorization
    double reference_ratio_ = 0.0;  // pivot ratio at the first factorization of the partition
    Eigen::VectorXd x_, w_n_, w_m_;
    std::vector<char> marks_;
};

}  // namespace mbd
