// Sparse LU of a square matrix whose sparsity pattern is fixed while its values change
// (the amalgamated formulation's block system, Eq. 4.20; J_d of a coordinate partition), with KLU (SuiteSparse, a
// third-party library): the pattern is ordered once (klu_analyze), factored with partial
// pivoting when asked (klu_factor, which allocates the factors), and otherwise refactored
// in place with the same pivot sequence (klu_refactor), which allocates nothing; solves are
// in place (klu_solve), also without allocating. A refactorization keeps the pivots of the
// last pivoting factorization, so the caller checks its solution (a residual) and asks
// for a pivoting factorization when that pivot sequence has gone bad.
#pragma once

#include <mbd/kit/own_order_fill.hpp>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <klu.h>

#include <utility>

namespace mbd {

class FixedPatternLU {
public:
    // No row scaling and no check of the input (KLU's scale = -1; the pattern is the caller's
    // own): a refactorization would recompute the scale factors at every evaluation, a third of
    // its cost on the amalgamated block system; the caller's residual check asks for new pivots
    // when the old ones no longer fit.
    FixedPatternLU() {
        klu_defaults(&common_);
        common_.scale = -1;
    }
    // partial_pivoting: every pivot is the largest entry of its column (KLU's tol = 1), so that
    // the pivots measure the matrix's conditioning (pivot_ratio()); otherwise KLU's default
    // threshold (diagonal preferred unless below 1e-3 of the column's largest entry)
    explicit FixedPatternLU(bool partial_pivoting) : FixedPatternLU() {
        if (partial_pivoting) common_.tol = 1.0;
    }
    FixedPatternLU(const FixedPatternLU&) = delete;
    FixedPatternLU& operator=(const FixedPatternLU&) = delete;
    ~FixedPatternLU() { clear(); }

    // A new pattern (K compressed, column-major): order it (KLU's AMD); the next factor() pivots.
    // From kCompareOrderingsFrom rows on (own_order_fill.hpp), that first factorization is also
    // made in K's own order, which is kept when its L and U have at most kOwnOrderSlack times
    // AMD's entries. It is tried only when the Cholesky fill of K + K^T in K's order is within the
    // same factor of AMD's estimate, so that an order that would fill a dense block is never
    // factored. Measured: a refactorization of the amalgamated block system of a 10,000-link
    // spatial chain cost 7.7 ns per factor entry in AMD's order (4.4 ns at 1,000 links); in K's own
    // order (the bodies, then the joints, in scene order) it has 11% fewer entries and costs 4.2 ns
    // per entry.
    bool analyze(Eigen::SparseMatrix<double>& K) {
        clear();
        symbolic_ = klu_analyze(static_cast<int>(K.rows()), K.outerIndexPtr(), K.innerIndexPtr(), &common_);
        compare_orderings_ = symbolic_ && K.rows() >= kCompareOrderingsFrom &&
                             2.0 * own_order_cholesky_entries(K) - K.rows() <= kOwnOrderSlack * (symbolic_->lnz + symbolic_->unz);
        return symbolic_ != nullptr;
    }

    // K's current values, on the analysed pattern: with partial pivoting (pivot, or when
    // there is no factorization yet), else with the pivots of the last pivoting one.
    bool factor(Eigen::SparseMatrix<double>& K, bool pivot) {
        if (!symbolic_) return false;
        if (pivot || !numeric_) {
            if (numeric_) klu_free_numeric(&numeric_, &common_);
            numeric_ = klu_factor(K.outerIndexPtr(), K.innerIndexPtr(), K.valuePtr(), symbolic_, &common_);
            if (numeric_ && compare_orderings_) keep_sparser_ordering(K);
            return numeric_ != nullptr;
        }
        return klu_refactor(K.outerIndexPtr(), K.innerIndexPtr(), K.valuePtr(), symbolic_, numeric_, &common_) != 0;
    }

    // exchanges the orderings, factors and settings with `other` (nothing is copied)
    void swap(FixedPatternLU& other) {
        std::swap(common_, other.common_);
        std::swap(symbolic_, other.symbolic_);
        std::swap(numeric_, other.numeric_);
        std::swap(compare_orderings_, other.compare_orderings_);
    }

    // x <- K^-1 x
    bool solve(Eigen::VectorXd& x) {
        return numeric_ && klu_solve(symbolic_, numeric_, static_cast<int>(x.size()), 1, x.data(), &common_) != 0;
    }
    // x <- K^-T x
    bool solve_transpose(Eigen::VectorXd& x) {
        return numeric_ && klu_tsolve(symbolic_, numeric_, static_cast<int>(x.size()), 1, x.data(), &common_) != 0;
    }
    // smallest / largest magnitude of the pivots (U's diagonal, unscaled) of
    // the current factorization; 0 without one
    double pivot_ratio() {
        if (!numeric_ || !klu_rcond(symbolic_, numeric_, &common_)) return 0.0;
        return common_.rcond;
    }

    // entries of L and U of the current factorization (0 without one)
    long factor_entries() const { return numeric_ ? static_cast<long>(numeric_->lnz) + numeric_->unz : 0; }


private:
    // after the first factorization of an analysed pattern: the same in K's own order, kept
    // when its L and U have no more entries
    void keep_sparser_ordering(Eigen::SparseMatrix<double>& K) {
        compare_orderings_ = false;
        const int n = static_cast<int>(K.rows());
        klu_symbolic* own = klu_analyze_given(n, K.outerIndexPtr(), K.innerIndexPtr(), nullptr, nullptr, &common_);
        klu_numeric* factors = own ? klu_factor(K.outerIndexPtr(), K.innerIndexPtr(), K.valuePtr(), own, &common_) : nullptr;
        if (factors && static_cast<double>(factors->lnz) + factors->unz <= kOwnOrderSlack * factor_entries()) {
            std::swap(own, symbolic_);
            std::swap(factors, numeric_);
        }
        if (factors) klu_free_numeric(&factors, &common_);
        if (own) klu_free_symbolic(&own, &common_);
    }

    void clear() {
        if (numeric_) klu_free_numeric(&numeric_, &common_);
        if (symbolic_) klu_free_symbolic(&symbolic_, &common_);
    }

    klu_common common_;
    klu_symbolic* symbolic_ = nullptr;
    klu_numeric* numeric_ = nullptr;
    bool compare_orderings_ = false;  // the next pivoting factorization also tries K's own order
};

}  // namespace mbd
