// S = W W^T (+ delta I) for a sparse W of fixed pattern (the augmented formulation's
// J M^-1 J^T with W = J Lm, book Eq. 6.141's coefficient matrix reduced to the multipliers),
// factored as L D L^T with the symbolic work done once: the fill-reducing ordering (AMD),
// the pattern of S and of its factor, and where each product W(i,c) W(j,c) lands in S.
// A factorization then only sums products into place and runs the numeric phase, so the
// evaluation path allocates nothing (up to Eigen's stack limit for its n-sized workspace,
// 128 KiB, i.e. 16,000 constraint rows).
#pragma once

#include <mbd/kit/block_mass_inverse.hpp>
#include <mbd/kit/system.hpp>

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include <vector>

namespace mbd {

// Eigen's L D L^T, factored straight from a matrix already in its ordering (its public
// factorize() builds an empty sparse matrix first, which allocates) and read in place.
class PreorderedLDLT
    : public Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Upper, Eigen::NaturalOrdering<int>> {
public:
    void factorize_preordered_matrix(const Eigen::SparseMatrix<double>& upper) {
        this->template factorize_preordered<true>(upper);
    }
    const Eigen::VectorXd& diagonal() const { return this->m_diag; }  // D (vectorD() returns a copy)
};

class SparseGram {
public:
    // W is rows x cols; rows_of_column[c]: the rows column c may hold, sorted and unique.
    void analyze(int rows, int cols, const std::vector<std::vector<int>>& rows_of_column);

    // The pattern of W = J Lm of a System: column c of body b holds every row of every joint
    // or driver that connects body b (J keeps that pattern for the life of the System).
    void analyze(System& system);

    // W's values in place (column-major, in the pattern's order), for the caller to fill.
    Eigen::SparseMatrix<double>& W() { return W_; }
    // W = J Lm (M^-1 = Lm Lm^T, per body); the rows marked in `left_out` (when given) are left
    // zero in W and decoupled in S (unit diagonal), so that their multipliers are their
    // right-hand sides (zero for rows that are dropped).
    void fill(const Eigen::SparseMatrix<double>& J, const BlockMassInverse& mass_inverse,
              const std::vector<char>* left_out = nullptr);
    // W = J (the Euclidean metric: S = J J^T)
    void fill(const Eigen::SparseMatrix<double>& J);

    // Factor S = W W^T + delta I. False when S is not numerically positive definite: a
    // pivot at or below 1e-14 of S's largest diagonal entry (dependent rows).
    bool factor(double delta);
    // The constraint row (original numbering) at the first pivot that failed, or -1.
    int failed_row() const { return failed_row_; }
    // The largest diagonal entry of the undamped S (after factor()).
    double max_diagonal() const { return max_diagonal_; }
    // ||S||_1 of the last factored S (its largest absolute column sum)
    double norm1();
    // The least pivot of the last factorization relative to its diagonal entry of S (damped,
    // when delta > 0): the squared sine of the angle between a row of W and the rows before it
    // in the ordering, near 0 when the rows are nearly dependent; 0 after a failure.
    double least_relative_pivot() const { return least_relative_pivot_; }
    // whether S is factored in its own order (the constraint rows' order), not AMD's: from
    // kCompareOrderingsFrom rows, when that fills at most kOwnOrderSlack times as much
    // (own_order_fill.hpp)
    bool own_order() const { return own_order_; }
    // x <- (W W^T + delta I)^-1 x, with `refinements` steps of iterative refinement
    // against the undamped W W^T.
    void solve(Eigen::VectorXd& x, int refinements);

private:
    template <int N>
    void fill_bodies(const Eigen::SparseMatrix<double>& J, const BlockMassInverse& mass_inverse);
    void solve_once(const Eigen::VectorXd& b, Eigen::VectorXd& x);
    double& entry_of_W(int row, int col);  // W's value at (row, col), which its pattern must hold

    Eigen::SparseMatrix<double> W_;
    Eigen::SparseMatrix<double> S_;   // P (W W^T) P^T, upper triangle, on its fixed pattern
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> P_;
    // Consecutive columns of W with the same rows (a body's nvb columns): their values are one
    // dense rows x columns block of W's value array (column-major), and their products land on
    // the same places of S_, so each pair of rows (a <= b) keeps one slot for the whole group.
    // On a planar chain this is 10 slots per body where a slot per product per column was 30
    // triples: the factorization's index stream is a ninth of what it was (the slots are read
    // again for each column of the group, from L1).
    struct ColumnGroup {
        int first_column, columns, rows;
        int first_pair;  // its slots in pair_slots_: (a, b) for a = 0..rows-1, b = a..rows-1
    };
    std::vector<ColumnGroup> groups_;
    std::vector<int> pair_slots_;
    std::vector<int> group_of_column_;
    std::vector<char> dense_body_;  // per body: J's columns hold W's rows (fill_bodies)
    std::vector<int> diagonal_;       // S_'s diagonal slot of each original row
    std::vector<int> original_row_;   // the original row of each row of S_
    std::vector<char> left_out_;      // rows decoupled by fill()
    PreorderedLDLT ldlt_;
    Eigen::VectorXd b_, y_, r_, w_, correction_, column_sums_;
    int failed_row_ = -1;
    bool own_order_ = false;
    double max_diagonal_ = 0.0;
    double least_relative_pivot_ = 0.0;
};

}  // namespace mbd
