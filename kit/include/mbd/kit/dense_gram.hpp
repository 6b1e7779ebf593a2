// S = J M^-1 J^T, dense, for small systems: the constraint rows' matrix in the
// kinetic-energy metric, of the augmented formulation (book Eq. 6.141) and of the
// coordinate projection (projection.hpp).
//
// Formed by body blocks: M is block diagonal, so S = sum_b J_b M_b^-1 J_b^T over the
// bodies, where J_b holds the rows of the joints and drivers that touch body b (a row
// touches at most two bodies). The rows of each body are read once from J's sparsity
// pattern, which is fixed for the life of a System; a product then costs
// sum_b k_b^2 n_b instead of the n_c^2 n_v of a dense W W^T.
//
// Factored by Cholesky with symmetric pivoting on the equilibrated matrix: each pivot is
// measured against its row's diagonal entry of S (so the rows' units and scales do not count),
// the largest such relative pivot is taken next, and the least one tells the caller how near
// to rank deficient S is: about the inverse of the condition of D S D, D = diag(S)^-1/2 (for a
// chain with mass ratios 1e12, 1e-12; for the car axis, whose unequilibrated pivots span 1e9,
// 1e-6). Written out because Eigen's LDL^T costs several times more on the few dozen rows of the
// dense path. A (nearly)
// rank deficient S is solved through the minimum-norm S^+ = (W^T)^+ W^+ with W = J Lm
// (M^-1 = Lm Lm^T), from complete orthogonal decompositions of W, whose condition is the
// square root of S's (singular values below 1e-10 of the largest count as zero).
//
// Rows in `decoupled` are left out: their entries of S are zero but for a unit diagonal
// scaled to S, so that their solution is their right-hand side over that scale (the caller
// zeroes it). All storage is sized by resize() and the first factorization: factoring and
// solving allocate nothing after that.
#pragma once

#include <mbd/kit/block_mass_inverse.hpp>
#include <mbd/kit/pseudo_inverse.hpp>

#include <Eigen/Dense>
#include <Eigen/Sparse>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace mbd {

class DenseGram {
public:
    void resize(int rows, int cols) {
        W_.setZero(rows, cols);
        S_.setZero(rows, rows);
        w_.setZero(cols);
        skip_.assign(rows, 0);
        // size the factorizations' storage once by computing on zeros (a size-constructed
        // Eigen decomposition leaves its status uninitialized: undefined behaviour when copied)
        if (rows > 0) {
            L_.setZero(rows, rows);
            inverse_diagonal_.setZero(rows);
            permuted_.setZero(rows);
            inverse_scale_.setZero(rows);
            order_.assign(rows, 0);
            cod_w_.compute(W_);
            cod_wt_.compute(W_.transpose());
        }
        pinv_w_.resize(rows, cols);
        pinv_wt_.resize(cols, rows);
        rows_of_body_.clear();
        slot_.clear();
        method_ = Method::Cholesky;
    }

    // Forms S = J M^-1 J^T and factors it. Returns the least relative pivot (see the header),
    // or 0 when a pivot is not positive: at or below about 1e-8, S is (nearly) rank deficient
    // or too ill-conditioned for the Cholesky solve.
    double factor(const Eigen::SparseMatrix<double>& J, const BlockMassInverse& m,
                  const std::vector<int>& decoupled = {}) {
        method_ = Method::Cholesky;
        if (S_.rows() == 0) return 1.0;
        form_S(J, m, decoupled);
        return cholesky();
    }

    // The minimum-norm path instead (after factor() or on its own).
    void factor_pseudo_inverse(const Eigen::SparseMatrix<double>& J, const BlockMassInverse& m,
                               const std::vector<int>& decoupled = {}) {
        form_W(J, m, decoupled);
        cod_w_.setThreshold(1e-10);
        cod_wt_.setThreshold(1e-10);
        cod_w_.compute(W_);
        cod_wt_.compute(W_.transpose());
        method_ = Method::PseudoInverse;
    }
    bool pseudo_inverse() const { return method_ == Method::PseudoInverse; }
    // The Cholesky path was taken (not the minimum-norm one): S x = b is solved by a backward
    // stable factorization, to a residual of round-off.
    bool well_conditioned() const { return method_ == Method::Cholesky && least_relative_pivot_ > 0.0; }
    // After the Cholesky path, its least pivot relative to the diagonal entry of S (the
    // squared sine of the angle between a row of W = J Lm and the rows eliminated before it,
    // about the inverse condition of the equilibrated S); else 0.
    double least_relative_pivot() const { return method_ == Method::Cholesky ? least_relative_pivot_ : 0.0; }

    // W = J Lm, its decoupled rows zero.
    const Eigen::MatrixXd& form_W(const Eigen::SparseMatrix<double>& J, const BlockMassInverse& m,
                                  const std::vector<int>& decoupled = {}) {
        const int nvb = m.velocities_per_body();
        W_.setZero();
        for (int col = 0; col < J.outerSize(); ++col) {
            if (col >= m.flexible_offset() && m.flexible_size() > 0) {  // the flexible bodies' dense block
                const int k = col - m.flexible_offset();
                for (Eigen::SparseMatrix<double>::InnerIterator it(J, col); it; ++it)
                    W_.row(it.row()).segment(m.flexible_offset(), m.flexible_size()) +=
                        it.value() * m.flexible_factor().row(k);
                continue;
            }
            const int b = col / nvb, k = col % nvb;
            for (Eigen::SparseMatrix<double>::InnerIterator it(J, col); it; ++it)
                W_.row(it.row()).segment(b * nvb, nvb) += it.value() * m.factor(b).row(k).head(nvb);
        }
        for (int r : decoupled) W_.row(r).setZero();
        return W_;
    }

    // x <- S^-1 x, or S^+ x after factor_pseudo_inverse().
    void solve(Eigen::VectorXd& x) {
        if (x.size() == 0) return;
        switch (method_) {
        case Method::Cholesky:
            cholesky_solve(x);
            break;
        case Method::PseudoInverse:
            pinv_w_.solve(cod_w_, x, w_);   // W^+ x
            pinv_wt_.solve(cod_wt_, w_, x);  // (W^T)^+ W^+ x
            break;
        }
    }

private:
    enum class Method { Cholesky, PseudoInverse };

    // The rows of each body, and where each of J's entries lands in its body's block, from
    // J's pattern (once: the pattern is fixed).
    void analyze(const Eigen::SparseMatrix<double>& J, int nvb) {
        const int bodies = static_cast<int>(J.cols()) / nvb;
        rows_of_body_.assign(bodies, {});
        for (int col = 0; col < J.outerSize(); ++col)
            for (Eigen::SparseMatrix<double>::InnerIterator it(J, col); it; ++it)
                rows_of_body_[col / nvb].push_back(static_cast<int>(it.row()));
        int most = 0;
        for (auto& rows : rows_of_body_) {
            std::sort(rows.begin(), rows.end());
            rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
            most = std::max(most, static_cast<int>(rows.size()));
        }
        slot_.assign(J.nonZeros(), 0);
        for (int col = 0; col < J.outerSize(); ++col) {
            const auto& rows = rows_of_body_[col / nvb];
            for (Eigen::Index p = J.outerIndexPtr()[col]; p < J.outerIndexPtr()[col + 1]; ++p)
                slot_[p] = static_cast<int>(std::lower_bound(rows.begin(), rows.end(), J.innerIndexPtr()[p]) -
                                            rows.begin());
        }
        body_rows_.assign(6 * most, 0.0);
        analyzed_nonzeros_ = J.nonZeros();
    }

    // The lower triangle of S, body block by body block (the header's sum).
    void form_S(const Eigen::SparseMatrix<double>& J, const BlockMassInverse& m, const std::vector<int>& decoupled) {
        if (m.flexible_size() > 0) {  // a flexible body's dense block: S = W W^T
            form_W(J, m, decoupled);
            S_.triangularView<Eigen::Lower>() = (W_ * W_.transpose()).eval();
            if (!decoupled.empty()) {
                const double unit = std::max(S_.diagonal().maxCoeff(), 1e-300);
                for (int r : decoupled) S_(r, r) = unit;
            }
            return;
        }
        const int nvb = m.velocities_per_body();
        if (rows_of_body_.empty() || analyzed_nonzeros_ != J.nonZeros()) analyze(J, nvb);
        for (int r : decoupled) skip_[r] = 1;
        S_.triangularView<Eigen::Lower>().setZero();
        for (int b = 0; b < static_cast<int>(rows_of_body_.size()); ++b) {
            if (nvb == 3)
                add_body<3>(J, m, b);
            else
                add_body<6>(J, m, b);
        }
        if (!decoupled.empty()) {
            const double unit = std::max(S_.diagonal().maxCoeff(), 1e-300);
            for (int r : decoupled) {
                S_(r, r) = unit;
                skip_[r] = 0;
            }
        }
    }

    // P S P^T = L L^T into L_'s lower triangle, taking next the largest pivot relative to its
    // row's diagonal entry of S (right-looking: each update is a contiguous column operation).
    // Returns the least relative pivot, 0 when a pivot is not positive.
    double cholesky() {
        const Eigen::Index n = S_.rows();
        L_.triangularView<Eigen::Lower>() = S_.triangularView<Eigen::Lower>();
        for (Eigen::Index k = 0; k < n; ++k) {
            order_[k] = static_cast<int>(k);
            if (!(S_(k, k) > 0.0)) return least_relative_pivot_ = 0.0;
            inverse_scale_[k] = 1.0 / S_(k, k);
        }
        double* l = L_.data();
        least_relative_pivot_ = 1.0;
        for (Eigen::Index k = 0; k < n; ++k) {
            Eigen::Index p = k;
            double largest = l[k * n + k] * inverse_scale_[k];
            for (Eigen::Index i = k + 1; i < n; ++i) {
                const double relative = l[i * n + i] * inverse_scale_[i];
                if (relative > largest) {
                    largest = relative;
                    p = i;
                }
            }
            if (p != k) swap_symmetric(k, p);
            double* column_k = l + k * n;
            const double pivot = column_k[k];
            if (!(pivot > 0.0)) return least_relative_pivot_ = 0.0;
            least_relative_pivot_ = std::min(least_relative_pivot_, largest);
            const double root = std::sqrt(pivot), inverse = 1.0 / root;
            column_k[k] = root;
            inverse_diagonal_[k] = inverse;
            for (Eigen::Index i = k + 1; i < n; ++i) column_k[i] *= inverse;
            for (Eigen::Index j = k + 1; j < n; ++j) subtract_multiple(l + j * n + j, column_k + j, column_k[j], n - j);
        }
        return least_relative_pivot_;
    }
    // Exchanges rows and columns k < p of the symmetric matrix whose lower triangle L_ holds
    // (columns before k already hold factor entries: their rows k and p trade places).
    void swap_symmetric(Eigen::Index k, Eigen::Index p) {
        const Eigen::Index n = L_.rows();
        double* l = L_.data();  // column-major: entry (i, j) at l[i + j * n]
        for (Eigen::Index j = 0; j < k; ++j) std::swap(l[k + j * n], l[p + j * n]);
        std::swap(l[k + k * n], l[p + p * n]);
        for (Eigen::Index i = k + 1; i < p; ++i) std::swap(l[i + k * n], l[p + i * n]);
        for (Eigen::Index i = p + 1; i < n; ++i) std::swap(l[i + k * n], l[i + p * n]);
        std::swap(order_[k], order_[p]);
        std::swap(inverse_scale_[k], inverse_scale_[p]);
    }
    // y -= a x over len entries: a column of the trailing update. The two never overlap (two
    // columns of L), and saying so lets the compiler vectorize the loop.
    static void subtract_multiple(double* __restrict y, const double* __restrict x, double a, Eigen::Index len) {
        for (Eigen::Index i = 0; i < len; ++i) y[i] -= a * x[i];
    }
    // x <- S^-1 x = P^T (L L^T)^-1 P x
    void cholesky_solve(Eigen::VectorXd& x) {
        const Eigen::Index n = L_.rows();
        const double* l = L_.data();
        double* y = permuted_.data();
        for (Eigen::Index k = 0; k < n; ++k) y[k] = x[order_[k]];
        for (Eigen::Index k = 0; k < n; ++k) {  // L y = P x, column by column
            const double* column_k = l + k * n;
            y[k] *= inverse_diagonal_[k];
            for (Eigen::Index i = k + 1; i < n; ++i) y[i] -= y[k] * column_k[i];
        }
        for (Eigen::Index k = n - 1; k >= 0; --k) {  // L^T z = y; row k of L^T is column k of L
            const double* column_k = l + k * n;
            double sum = y[k];
            for (Eigen::Index i = k + 1; i < n; ++i) sum -= column_k[i] * y[i];
            y[k] = sum * inverse_diagonal_[k];
        }
        for (Eigen::Index k = 0; k < n; ++k) x[order_[k]] = y[k];
    }

    // S += J_b M_b^-1 J_b^T on body b's rows (N velocities per body); the rows of J_b and of
    // J_b M_b^-1 contiguous, so that each entry of S is one N-long dot product
    template <int N>
    void add_body(const Eigen::SparseMatrix<double>& J, const BlockMassInverse& m, int b) {
        using Row = Eigen::Matrix<double, 1, N>;
        const auto& rows = rows_of_body_[b];
        const int k = static_cast<int>(rows.size());
        if (k == 0) return;
        double* jb = body_rows_.data();
        std::fill(jb, jb + k * N, 0.0);
        for (int c = 0; c < N; ++c) {
            const int col = b * N + c;
            for (Eigen::Index p = J.outerIndexPtr()[col]; p < J.outerIndexPtr()[col + 1]; ++p)
                if (!skip_[J.innerIndexPtr()[p]]) jb[slot_[p] * N + c] = J.valuePtr()[p];
        }
        const Eigen::Matrix<double, N, N> minv = m.inverse(b);
        const Eigen::Index n = S_.rows();
        double* s = S_.data();
        for (int i = 0; i < k; ++i) {
            const Row x = Eigen::Map<const Row>(jb + i * N) * minv;  // a local: S's stores cannot alias it
            double* row_i = s + rows[i];
            for (int j = 0; j <= i; ++j) row_i[rows[j] * n] += x.dot(Eigen::Map<const Row>(jb + j * N));
        }
    }

    Eigen::MatrixXd W_, S_;
    Eigen::VectorXd w_;
    std::vector<char> skip_;
    std::vector<std::vector<int>> rows_of_body_;
    std::vector<int> slot_;  // per entry of J: its row's place in its body's rows
    Eigen::Index analyzed_nonzeros_ = -1;
    std::vector<double> body_rows_;  // J_b, row by row
    Eigen::MatrixXd L_;  // the Cholesky factor, lower
    Eigen::VectorXd inverse_diagonal_;  // 1 / L(i, i)
    Eigen::VectorXd permuted_;          // P x
    Eigen::VectorXd inverse_scale_;     // 1 / S(i, i) of the row now at place i of P S P^T
    std::vector<int> order_;            // row k of P S P^T is row order_[k] of S
    Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod_w_, cod_wt_;
    PseudoInverseSolver pinv_w_, pinv_wt_;
    Method method_ = Method::Cholesky;
    double least_relative_pivot_ = 0.0;
};

}  // namespace mbd
