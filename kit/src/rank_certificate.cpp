// The certificate of full row rank: see rank_certificate.hpp.
#include <mbd/kit/rank_certificate.hpp>

#include <algorithm>
#include <cmath>

namespace mbd {

void RankCertificate::bind(System& system, SingularityMonitor& monitor) {
    monitor.certificate = nullptr;
    // G's block pattern covers the rigid bodies' columns only (sparse_gram.hpp): a scene with
    // flexible bodies gets no certificate, and the monitor does its QR
    rows_ = monitor.active(system) && system.flexible_coordinates() == 0 ? system.constraint_rows(true) : 0;
    if (rows_ == 0) return;
    monitor.certificate = this;
    reuse_above_ = 2.0 * 10.0 * monitor.tolerance;  // twice what the monitor needs to skip its QR
    gram_.analyze(system);
    anchored_ = false;
    anchor_values_.reserve(gram_.W().nonZeros());  // J's entries lie in W's block pattern
    anchor_inner_.reserve(gram_.W().nonZeros());
    anchor_outer_.reserve(gram_.W().outerSize() + 1);
    x_.setZero(rows_);
    y_.setZero(rows_);
    z_.setZero(rows_);
}

double RankCertificate::sigma_ratio_bound(const Eigen::SparseMatrix<double>& J) {
    if (rows_ == 0 || J.rows() != rows_) return 0.0;
    if (anchored_) {
        const double moved = bound_from_anchor(J);
        if (moved >= std::min(reuse_above_, 0.5 * anchor_bound_)) return moved;
    }
    anchored_ = false;
    ++factorizations_;
    inverse_norm_ = 0.0;
    gram_.fill(J);
    if (!gram_.factor(0.0)) return 0.0;
    inverse_norm_ = estimate_inverse_norm1();
    const double sigma_min = 1.0 / std::sqrt(inverse_norm_ * safety), sigma_max = std::sqrt(gram_.norm1());
    const double bound = sigma_min / sigma_max;
    if (!std::isfinite(bound) || !(bound > 0.0)) return 0.0;
    const size_t nnz = static_cast<size_t>(J.nonZeros()), outer = static_cast<size_t>(J.outerSize()) + 1;
    if (!J.isCompressed() || nnz > anchor_values_.capacity() || outer > anchor_outer_.capacity()) return bound;
    anchor_values_.assign(J.valuePtr(), J.valuePtr() + nnz);
    anchor_inner_.assign(J.innerIndexPtr(), J.innerIndexPtr() + nnz);
    anchor_outer_.assign(J.outerIndexPtr(), J.outerIndexPtr() + outer);
    anchor_sigma_min_ = sigma_min;
    anchor_sigma_max_ = sigma_max;
    anchor_bound_ = bound;
    anchored_ = true;
    return bound;
}

double RankCertificate::bound_from_anchor(const Eigen::SparseMatrix<double>& J) const {
    const size_t nnz = static_cast<size_t>(J.nonZeros()), outer = static_cast<size_t>(J.outerSize()) + 1;
    if (!J.isCompressed() || nnz != anchor_values_.size() || outer != anchor_outer_.size() ||
        !std::equal(anchor_outer_.begin(), anchor_outer_.end(), J.outerIndexPtr()) ||
        !std::equal(anchor_inner_.begin(), anchor_inner_.end(), J.innerIndexPtr()))
        return -1.0;
    double squares = 0.0;  // ||J - J_a||_F^2 >= ||J - J_a||_2^2
    for (size_t k = 0; k < nnz; ++k) squares += (J.valuePtr()[k] - anchor_values_[k]) * (J.valuePtr()[k] - anchor_values_[k]);
    const double moved = std::sqrt(squares);
    if (!std::isfinite(moved)) return -1.0;
    const double least = anchor_sigma_min_ - moved;
    return least > 0.0 ? least / (anchor_sigma_max_ + moved) : 0.0;
}

// Hager's estimate of ||G^-1||_1 for symmetric G (G^-T = G^-1): at most five ascent steps from
// x = e / n, then Higham's alternating vector, which catches the cases the ascent misses.
double RankCertificate::estimate_inverse_norm1() {
    const int n = rows_;
    x_.setConstant(1.0 / n);
    double estimate = 0.0;
    int last_index = -1;
    for (int pass = 0; pass < 5; ++pass) {
        y_ = x_;
        gram_.solve(y_, 0);
        const double norm = y_.lpNorm<1>();
        if (pass > 0 && norm <= estimate) break;
        estimate = norm;
        for (int i = 0; i < n; ++i) z_[i] = y_[i] >= 0.0 ? 1.0 : -1.0;
        gram_.solve(z_, 0);
        int index = 0;
        const double largest = z_.cwiseAbs().maxCoeff(&index);
        if (pass > 0 && (index == last_index || largest <= z_.dot(x_))) break;
        last_index = index;
        x_.setZero();
        x_[index] = 1.0;
    }
    for (int i = 0; i < n; ++i) x_[i] = (i % 2 == 0 ? 1.0 : -1.0) * (1.0 + (n > 1 ? double(i) / (n - 1) : 0.0));
    gram_.solve(x_, 0);
    const double alternating = 2.0 * x_.lpNorm<1>() / (3.0 * n);
    return std::isfinite(estimate) && std::isfinite(alternating) ? std::max(estimate, alternating)
                                                                  : HUGE_VAL;
}

}  // namespace mbd
