// The velocity transformation through a sparse LU of J_d: see sparse_velocity_transform.hpp.
#include <mbd/kit/sparse_velocity_transform.hpp>

#include <utility>

namespace mbd {

void SparseVelocityTransform::select(const Eigen::SparseMatrix<double>& J, const CoordinatePartition& p) {
    p_ = &p;
    const int m = static_cast<int>(J.rows()), n = static_cast<int>(J.cols());
    std::vector<int> row_position(m, -1), column_position(n, -1);
    for (int i = 0; i < p.rank; ++i) {
        row_position[p.rows[i]] = i;
        column_position[p.dependent[i]] = i;
    }
    std::vector<Eigen::Triplet<double>> entries;
    for (int c = 0; c < n; ++c)
        if (column_position[c] >= 0)
            for (Eigen::SparseMatrix<double>::InnerIterator it(J, c); it; ++it)
                if (row_position[it.row()] >= 0) entries.emplace_back(row_position[it.row()], column_position[c], 1.0);
    Jd_.resize(p.rank, p.rank);
    Jd_.setFromTriplets(entries.begin(), entries.end());
    Jd_.makeCompressed();
    slot_.assign(J.nonZeros(), -1);
    int e = 0;
    for (int c = 0; c < n; ++c)
        for (Eigen::SparseMatrix<double>::InnerIterator it(J, c); it; ++it, ++e)
            if (column_position[c] >= 0 && row_position[it.row()] >= 0)
                slot_[e] = static_cast<int>(&Jd_.coeffRef(row_position[it.row()], column_position[c]) - Jd_.valuePtr());
    pivoted_ = false;
    reference_ratio_ = 0.0;
    if (p.rank > 0) lu_.analyze(Jd_);
    x_.setZero(p.rank);
    w_n_.setZero(n);
    w_m_.setZero(m);
}

void SparseVelocityTransform::swap(SparseVelocityTransform& other) {
    std::swap(p_, other.p_);
    Jd_.swap(other.Jd_);
    slot_.swap(other.slot_);
    lu_.swap(other.lu_);
    std::swap(pivoted_, other.pivoted_);
    std::swap(pivoted_ratio_, other.pivoted_ratio_);
    std::swap(reference_ratio_, other.reference_ratio_);
    x_.swap(other.x_);
    w_n_.swap(other.w_n_);
    w_m_.swap(other.w_m_);
    marks_.swap(other.marks_);
}

bool SparseVelocityTransform::same_dependent_columns(const CoordinatePartition& other) {
    const CoordinatePartition& p = *p_;
    if (other.rank != p.rank || other.redundant != p.redundant) return false;
    marks_.assign(w_n_.size(), 0);
    for (int c : p.dependent) marks_[c] = 1;
    for (int c : other.dependent)
        if (!marks_[c]) return false;
    return true;
}

bool SparseVelocityTransform::factor(const Eigen::SparseMatrix<double>& J) {
    if (p_->rank == 0) return true;
    double* values = Jd_.valuePtr();
    int e = 0;
    for (int c = 0; c < J.outerSize(); ++c)
        for (Eigen::SparseMatrix<double>::InnerIterator it(J, c); it; ++it, ++e)
            if (slot_[e] >= 0) values[slot_[e]] = it.value();
    // the old pivots fit while the pivot ratio stays within a factor 1000 of the one they were
    // chosen at; otherwise pivot again (a new factorization: it allocates, rarely)
    if (pivoted_ && lu_.factor(Jd_, false) && lu_.pivot_ratio() >= 1e-3 * pivoted_ratio_) return true;
    const bool first = !pivoted_ && reference_ratio_ == 0.0;
    pivoted_ = lu_.factor(Jd_, true);
    pivoted_ratio_ = pivoted_ ? lu_.pivot_ratio() : 0.0;
    if (first) reference_ratio_ = pivoted_ratio_;
    return pivoted_ && pivoted_ratio_ > 0.0;
}

void SparseVelocityTransform::velocities(const Eigen::SparseMatrix<double>& J, const Eigen::VectorXd& C_t,
                                         const Eigen::VectorXd& vi, Eigen::VectorXd& v) {
    const CoordinatePartition& p = *p_;
    v.setZero(J.cols());
    for (size_t c = 0; c < p.independent.size(); ++c) v[p.independent[c]] = vi[c];
    if (p.rank == 0) return;
    w_m_.noalias() = J * v;  // J_i v_i (v_d = 0)
    w_m_ += C_t;
    w_m_ = -w_m_;
    solve_dependent(w_m_, v);
}

bool SparseVelocityTransform::solve_dependent(const Eigen::VectorXd& b, Eigen::VectorXd& dv) {
    const CoordinatePartition& p = *p_;
    for (int i = 0; i < p.rank; ++i) x_[i] = b[p.rows[i]];
    if (p.rank > 0 && !lu_.solve(x_)) return false;
    for (int i = 0; i < p.rank; ++i) dv[p.dependent[i]] = x_[i];
    return x_.allFinite();
}

void SparseVelocityTransform::transpose_times(const Eigen::SparseMatrix<double>& J, const Eigen::VectorXd& x,
                                              Eigen::VectorXd& out) {
    const CoordinatePartition& p = *p_;
    const int k = static_cast<int>(p.independent.size());
    out.resize(k);
    for (int c = 0; c < k; ++c) out[c] = x[p.independent[c]];
    if (p.rank == 0) return;
    dependent_multipliers(x, w_m_);
    w_n_.noalias() = J.transpose() * w_m_;
    for (int c = 0; c < k; ++c) out[c] -= w_n_[p.independent[c]];
}

void SparseVelocityTransform::dependent_multipliers(const Eigen::VectorXd& x, Eigen::VectorXd& mu) {
    const CoordinatePartition& p = *p_;
    mu.setZero(w_m_.size());
    if (p.rank == 0) return;
    for (int i = 0; i < p.rank; ++i) x_[i] = x[p.dependent[i]];
    lu_.solve_transpose(x_);  // J_d^T mu = x_d
    for (int i = 0; i < p.rank; ++i) mu[p.rows[i]] = x_[i];
}

}  // namespace mbd
