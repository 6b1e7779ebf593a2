// A certificate that J has full row rank, well enough that the singular-configuration check's
// QR (kit singularity.hpp) can be skipped: a lower bound on sigma_min(J) / sigma_max(J), from a
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
//
// Between steps J moves little, so a factorization is an anchor for the next calls: by Weyl's
// inequality every singular value moves by at most ||J - J_a||_2 <= ||J - J_a||_F = d, so
//     sigma_min(J) / sigma_max(J) >= (s_a - d) / (S_a + d)
// with s_a = 1 / sqrt(safety ||G_a^-1||_1 estimate) <= sigma_min(J_a) and S_a = sqrt(||G_a||_1)
// >= sigma_max(J_a). While that bound is at least twice what the monitor needs to skip its QR
// (2 x 10 x tolerance; or half the anchor's own, if that is less), it is returned at the cost of
// one pass over J's entries (same pattern); otherwise J is factored afresh and becomes the
// anchor. A singular J can never be certified this way (its bound would be <= 0).
#pragma once

#include <mbd/kit/sparse_gram.hpp>

#include <mbd/kit/singularity.hpp>
#include <mbd/kit/system.hpp>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <vector>

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

    // the estimate of ||G^-1||_1 at the last factorization (for tests)
    double inverse_norm1_estimate() const { return inverse_norm_; }
    // how many calls factored G (the others were answered from the anchor; for tests)
    long factorizations() const { return factorizations_; }

private:
    double estimate_inverse_norm1();
    // the anchor's bound moved to J (Weyl), or -1 when J does not have the anchor's pattern
    double bound_from_anchor(const Eigen::SparseMatrix<double>& J) const;

    SparseGram gram_;
    int rows_ = 0;
    double inverse_norm_ = 0.0;
    long factorizations_ = 0;
    // the anchor: J's entries and pattern at the last factorization, its sigma bounds
    // (capacity reserved at bind for J's block pattern: anchoring allocates nothing)
    bool anchored_ = false;
    std::vector<double> anchor_values_;
    std::vector<int> anchor_inner_, anchor_outer_;
    double anchor_sigma_min_ = 0.0, anchor_sigma_max_ = 0.0, anchor_bound_ = 0.0;
    double reuse_above_ = 0.0;  // an answer from the anchor at least this (or half the anchor's) stands
    Eigen::VectorXd x_, y_, z_;
};

}  // namespace mbd
