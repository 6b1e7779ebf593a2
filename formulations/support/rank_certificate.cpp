// The certificate of full row rank: see rank_certificate.hpp.
#include "rank_certificate.hpp"

#include <algorithm>
#include <cmath>

namespace mbd {

void RankCertificate::bind(System& system, SingularityMonitor& monitor) {
    monitor.certificate = nullptr;
    rows_ = monitor.active(system) ? system.constraint_rows(true) : 0;
    if (rows_ == 0) return;
    monitor.certificate = this;
    gram_.analyze(system);
    x_.setZero(rows_);
    y_.setZero(rows_);
    z_.setZero(rows_);
}

double RankCertificate::sigma_ratio_bound(const Eigen::SparseMatrix<double>& J) {
    inverse_norm_ = 0.0;
    if (rows_ == 0 || J.rows() != rows_) return 0.0;
    gram_.fill(J);
    if (!gram_.factor(0.0)) return 0.0;
    inverse_norm_ = estimate_inverse_norm1();
    const double condition = gram_.norm1() * inverse_norm_ * safety;
    return std::isfinite(condition) && condition > 0.0 ? 1.0 / std::sqrt(condition) : 0.0;
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
