// A certificate that J has full row rank, well enough that the singular-configuration check's
// QR (sdk singularity.hpp) can be skipped: a lower bound on sigma_min(J) / sigma_max(J), from a
// sparse L D L^T of G = J J^T (pattern analysed once, support/sparse_gram.hpp) and an estimate of
// ||G^-1||_1 by Hager's method with Higham's extra vector (Higham, "Accuracy and Stability of
// Numerical Algorithms", 2nd ed., Alg. 15.4 and Sec. 15.3, the LAPACK estimator).
//
// Why it bounds the QR's pivots: for the column-pivoted QR of J^T, |R_00| <= sigma_max and every
// |R_kk| >= sigma_min (a triangular matrix's least singular value is at most each of its diagonal
// entries), so |R_kk| / |R_00| >= sigma_min / sigma_max. For symmetric G, the 2-norm is at most
// the 1-norm, so cond_2(G) = (sigma_max / sigma_min)^2 <= ||G||_1 ||G^-1||_1. The estimate of
// ||G^-1||_1 is a lower bound, in practice within a factor 3; a factor `safety` = 10 covers it.
//
// Unlike the screen by S = J M^-1 J^T's pivots, it does not depend on the mass matrix: a chain of
// rods with a tiny axial inertia (cond M ~ 1e9) is certified as readily as one of spheres. Cost:
// one sparse factorization and at most 12 solves with it, O(n) on a chain; no allocation.
#pragma once

#include "sparse_gram.hpp"

#include <mbd/sdk/singularity.hpp>
#include <mbd/sdk/system.hpp>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace mbd {

class RankCertificate final : public FullRankCertificate {
public:
    static constexpr double safety = 10.0;

    // G's pattern: the System's joint and driver rows (velocity-level rows are not covered:
    // a J with more rows gets no certificate); then lent to the monitor, when its check is active
    // (set its tolerance first)
    void bind(System& system, SingularityMonitor& monitor);

    // A lower bound on sigma_min(J) / sigma_max(J); 0 when there is none (G not numerically
    // positive definite, or J not of the bound System's rows).
    double sigma_ratio_bound(const Eigen::SparseMatrix<double>& J) override;

    // the estimate of ||G^-1||_1 after a successful sigma_ratio_bound (for tests)
    double inverse_norm1_estimate() const { return inverse_norm_; }

private:
    double estimate_inverse_norm1();

    SparseGram gram_;
    int rows_ = 0;
    double inverse_norm_ = 0.0;
    Eigen::VectorXd x_, y_, z_;
};

}  // namespace mbd
