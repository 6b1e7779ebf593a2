// Sparse LU of a square matrix whose sparsity pattern is fixed while its values change
// (the amalgamated formulation's block system, Eq. 4.20; J_d of a coordinate partition), with KLU (SuiteSparse, a
// third-party library): the pattern is ordered once (klu_analyze), factored with partial
// pivoting when asked (klu_factor, which allocates the factors), and otherwise refactored
// in place with the same pivot sequence (klu_refactor), which allocates nothing; solves are
// in place (klu_solve), also without allocating. A refactorization keeps the pivots of the
// last pivoting factorization, so the caller checks its solution (a residual) and asks
// for a pivoting factorization when that pivot sequence has gone bad.
#pragma once

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

    // A new pattern (K compressed, column-major): order it; the next factor() pivots.
    bool analyze(Eigen::SparseMatrix<double>& K) {
        clear();
        symbolic_ = klu_analyze(static_cast<int>(K.rows()), K.outerIndexPtr(), K.innerIndexPtr(), &common_);
        return symbolic_ != nullptr;
    }

    // K's current values, on the analysed pattern: with partial pivoting (pivot, or when
    // there is no factorization yet), else with the pivots of the last pivoting one.
    bool factor(Eigen::SparseMatrix<double>& K, bool pivot) {
        if (!symbolic_) return false;
        if (pivot || !numeric_) {
            if (numeric_) klu_free_numeric(&numeric_, &common_);
            numeric_ = klu_factor(K.outerIndexPtr(), K.innerIndexPtr(), K.valuePtr(), symbolic_, &common_);
            return numeric_ != nullptr;
        }
        return klu_refactor(K.outerIndexPtr(), K.innerIndexPtr(), K.valuePtr(), symbolic_, numeric_, &common_) != 0;
    }

    // exchanges the orderings, factors and settings with `other` (nothing is copied)
    void swap(FixedPatternLU& other) {
        std::swap(common_, other.common_);
        std::swap(symbolic_, other.symbolic_);
        std::swap(numeric_, other.numeric_);
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

private:
    void clear() {
        if (numeric_) klu_free_numeric(&numeric_, &common_);
        if (symbolic_) klu_free_symbolic(&symbolic_, &common_);
    }

    klu_common common_;
    klu_symbolic* symbolic_ = nullptr;
    klu_numeric* numeric_ = nullptr;
};

}  // namespace mbd
