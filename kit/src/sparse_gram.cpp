#include <mbd/kit/sparse_gram.hpp>

#include <mbd/kit/own_order_fill.hpp>

#include <Eigen/OrderingMethods>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace mbd {

namespace {

// The upper pattern of W W^T: every pair of rows that share a column, and the diagonal.
Eigen::SparseMatrix<double> upper_gram_pattern(const Eigen::SparseMatrix<double>& W) {
    const int rows = static_cast<int>(W.rows());
    std::vector<Eigen::Triplet<double>> s_entries;
    for (int r = 0; r < rows; ++r) s_entries.emplace_back(r, r, 1.0);
    for (int c = 0; c < W.outerSize(); ++c)
        for (Eigen::SparseMatrix<double>::InnerIterator a(W, c); a; ++a)
            for (Eigen::SparseMatrix<double>::InnerIterator b(W, c); b; ++b)
                if (a.row() <= b.row()) s_entries.emplace_back(a.row(), b.row(), 1.0);
    Eigen::SparseMatrix<double> S(rows, rows);
    S.setFromTriplets(s_entries.begin(), s_entries.end());
    S.makeCompressed();
    return S;
}

}  // namespace

void SparseGram::analyze(System& system) {
    const int bodies = system.body_count(), nvb = velocities_per_body(system.dimension());
    std::vector<std::vector<int>> rows_of_body(bodies);
    auto add_rows = [&](const std::vector<int>& connected, int first, int count) {
        for (int body : connected)
            if (body >= 0)
                for (int r = first; r < first + count; ++r) rows_of_body[body].push_back(r);
    };
    for (int j = 0; j < system.joint_count(); ++j) add_rows(system.joint(j).bodies, system.joint(j).first_row, system.joint(j).rows);
    for (int d = 0; d < system.driver_count(); ++d)
        add_rows(system.joint(system.driver(d).joint).bodies, system.driver(d).row, 1);
    std::vector<std::vector<int>> rows_of_column(bodies * nvb);
    for (int b = 0; b < bodies; ++b) {
        auto& rows = rows_of_body[b];
        std::sort(rows.begin(), rows.end());
        rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
        for (int c = 0; c < nvb; ++c) rows_of_column[b * nvb + c] = rows;
    }
    analyze(system.constraint_rows(true), bodies * nvb, rows_of_column);
}

void SparseGram::fill(const Eigen::SparseMatrix<double>& J, const BlockMassInverse& mass_inverse,
                      const std::vector<char>* left_out) {
    if (left_out)
        left_out_ = *left_out;
    else
        std::fill(left_out_.begin(), left_out_.end(), 0);
    if (mass_inverse.velocities_per_body() == 3)
        fill_bodies<3>(J, mass_inverse);
    else
        fill_bodies<6>(J, mass_inverse);
}

// Body by body: where J's columns of the body hold exactly W's rows (a System's J does: every
// row of a joint has all nvb entries of each of its bodies), W_b = J_b Lm_b is one small dense
// product of the two value blocks; otherwise entry by entry. Which bodies are dense is read
// from the first J after analyze(): a System's J keeps its pattern for the System's life
// (kit/system.hpp), so later J are not compared index by index (that alone was a pass over
// J's row indices per rhs).
template <int N>
void SparseGram::fill_bodies(const Eigen::SparseMatrix<double>& J, const BlockMassInverse& mass_inverse) {
    const int* outer = W_.outerIndexPtr();
    const int* inner = W_.innerIndexPtr();
    double* w = W_.valuePtr();
    const int* j_outer = J.outerIndexPtr();
    const int* j_inner = J.innerIndexPtr();
    const double* j_values = J.valuePtr();
    const int bodies = static_cast<int>(J.cols()) / N;
    if (dense_body_.size() != static_cast<size_t>(bodies)) {
        dense_body_.assign(bodies, 0);
        for (int b = 0; b < bodies; ++b) {
            const int c0 = b * N, k = outer[c0 + 1] - outer[c0];
            bool dense = J.isCompressed() && group_of_column_[c0] == group_of_column_[c0 + N - 1];
            for (int c = c0; dense && c < c0 + N; ++c)
                dense = j_outer[c + 1] - j_outer[c] == k &&
                        std::equal(j_inner + j_outer[c], j_inner + j_outer[c + 1], inner + outer[c0]);
            dense_body_[b] = dense;
        }
    }
    for (int b = 0; b < bodies; ++b) {
        const int c0 = b * N, k = outer[c0 + 1] - outer[c0];
        const Eigen::Map<const Eigen::Matrix<double, N, N>> L(mass_inverse.factor(b).data());
        if (dense_body_[b] && J.isCompressed()) {
            using Block = Eigen::Matrix<double, Eigen::Dynamic, N>;
            Eigen::Map<Block> Wb(w + outer[c0], k, N);
            Wb.noalias() = Eigen::Map<const Block>(j_values + j_outer[c0], k, N).lazyProduct(L);
            for (int a = 0; a < k; ++a)
                if (left_out_[inner[outer[c0] + a]]) Wb.row(a).setZero();
            continue;
        }
        std::fill(w + outer[c0], w + outer[c0 + N], 0.0);
        for (int i = 0; i < N; ++i)
            for (Eigen::SparseMatrix<double>::InnerIterator it(J, c0 + i); it; ++it) {
                if (left_out_[it.row()]) continue;
                for (int j = 0; j <= i; ++j)
                    if (L(i, j) != 0.0) entry_of_W(static_cast<int>(it.row()), c0 + j) += it.value() * L(i, j);
            }
    }
}

void SparseGram::fill(const Eigen::SparseMatrix<double>& J) {
    std::fill(W_.valuePtr(), W_.valuePtr() + W_.nonZeros(), 0.0);
    std::fill(left_out_.begin(), left_out_.end(), 0);
    for (int c = 0; c < J.outerSize(); ++c)
        for (Eigen::SparseMatrix<double>::InnerIterator it(J, c); it; ++it)
            entry_of_W(static_cast<int>(it.row()), c) = it.value();
}

double& SparseGram::entry_of_W(int row, int col) {
    const int* wi = W_.innerIndexPtr();
    const int* begin = wi + W_.outerIndexPtr()[col];
    const int* end = wi + W_.outerIndexPtr()[col + 1];
    const int* pos = std::lower_bound(begin, end, row);
    if (pos == end || *pos != row)
        throw std::logic_error("sparse J M^-1 J^T: a Jacobian entry outside its joint's bodies (row " +
                               std::to_string(row) + ")");
    return W_.valuePtr()[pos - wi];
}

double SparseGram::norm1() {
    column_sums_.setZero();
    const double* s = S_.valuePtr();
    for (int j = 0; j < S_.outerSize(); ++j)
        for (int k = S_.outerIndexPtr()[j]; k < S_.outerIndexPtr()[j + 1]; ++k) {
            const int i = S_.innerIndexPtr()[k];
            column_sums_[j] += std::abs(s[k]);
            if (i != j) column_sums_[i] += std::abs(s[k]);  // the lower triangle's mirror
        }
    return column_sums_.size() > 0 ? column_sums_.maxCoeff() : 0.0;
}

void SparseGram::analyze(int rows, int cols, const std::vector<std::vector<int>>& rows_of_column) {
    // W's pattern
    std::vector<Eigen::Triplet<double>> w_entries;
    for (int c = 0; c < cols; ++c)
        for (int r : rows_of_column[c]) w_entries.emplace_back(r, c, 1.0);
    W_.resize(rows, cols);
    W_.setFromTriplets(w_entries.begin(), w_entries.end());
    W_.makeCompressed();

    Eigen::SparseMatrix<double> S = upper_gram_pattern(W_);
    auto slot_of = [&](int i, int j) {  // S(i, j), i <= j, in S's value array
        const int* begin = S.innerIndexPtr() + S.outerIndexPtr()[j];
        const int* end = S.innerIndexPtr() + S.outerIndexPtr()[j + 1];
        return static_cast<int>(std::lower_bound(begin, end, i) - S.innerIndexPtr());
    };

    // the ordering, and S's entries followed into P S P^T by their numbers
    Eigen::AMDOrdering<int> amd;
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> inverse;
    amd(S.selfadjointView<Eigen::Upper>(), inverse);
    P_ = inverse.inverse();
    own_order_ = false;
    if (rows >= kCompareOrderingsFrom) {  // S's own order, when it fills at most kOwnOrderSlack times AMD's
        Eigen::SparseMatrix<double> ordered(rows, rows);
        ordered.selfadjointView<Eigen::Upper>() = S.selfadjointView<Eigen::Upper>().twistedBy(P_);
        own_order_ = own_order_cholesky_entries(S) <= kOwnOrderSlack * own_order_cholesky_entries(ordered);
        if (own_order_) P_.setIdentity(rows);
    }
    for (int k = 0; k < S.nonZeros(); ++k) S.valuePtr()[k] = k + 1;
    S_.resize(rows, rows);
    S_.selfadjointView<Eigen::Upper>() = S.selfadjointView<Eigen::Upper>().twistedBy(P_);
    S_.makeCompressed();
    std::vector<int> moved(S.nonZeros(), -1);
    for (int k = 0; k < S_.nonZeros(); ++k) moved[static_cast<int>(S_.valuePtr()[k]) - 1] = k;

    groups_.clear();
    pair_slots_.clear();
    dense_body_.clear();  // read again from the next J
    group_of_column_.assign(cols, -1);
    const int* outer = W_.outerIndexPtr();
    const int* inner = W_.innerIndexPtr();
    for (int c = 0; c < cols;) {
        const int rows_c = outer[c + 1] - outer[c];
        int end = c + 1;  // the run of columns with column c's rows
        while (end < cols && outer[end + 1] - outer[end] == rows_c &&
               std::equal(inner + outer[c], inner + outer[c + 1], inner + outer[end]))
            ++end;
        groups_.push_back({c, end - c, rows_c, static_cast<int>(pair_slots_.size())});
        for (int a = outer[c]; a < outer[c + 1]; ++a)
            for (int b = a; b < outer[c + 1]; ++b) pair_slots_.push_back(moved[slot_of(inner[a], inner[b])]);
        for (int k = c; k < end; ++k) group_of_column_[k] = static_cast<int>(groups_.size()) - 1;
        c = end;
    }
    diagonal_.resize(rows);
    original_row_.resize(rows);
    for (int r = 0; r < rows; ++r) {
        diagonal_[r] = moved[slot_of(r, r)];
        original_row_[P_.indices()[r]] = r;  // (P x)[indices[r]] = x[r]
    }
    for (int k = 0; k < S_.nonZeros(); ++k) S_.valuePtr()[k] = 0.0;
    for (int r = 0; r < rows; ++r) S_.valuePtr()[diagonal_[r]] = 1.0;
    ldlt_.analyzePattern(S_);
    if (ldlt_.info() != Eigen::Success) throw std::runtime_error("augmented formulation: analysis of J M^-1 J^T failed");
    ldlt_.factorize_preordered_matrix(S_);  // of the unit diagonal: sizes D, so that factor() allocates nothing
    left_out_.assign(rows, 0);
    b_.setZero(rows);
    y_.setZero(rows);
    r_.setZero(rows);
    correction_.setZero(rows);
    column_sums_.setZero(rows);
    w_.setZero(cols);
}

bool SparseGram::factor(double delta) {
    double* s = S_.valuePtr();
    const double* w = W_.valuePtr();
    std::fill(s, s + S_.nonZeros(), 0.0);
    const int* outer = W_.outerIndexPtr();
    for (const ColumnGroup& g : groups_) {
        const int k = g.rows;
        // column by column, each product added where it lands (the group's few slots stay in
        // L1): the same order of summation as one product at a time
        for (int c = 0; c < g.columns; ++c) {
            const double* column = w + outer[g.first_column + c];
            const int* slot = pair_slots_.data() + g.first_pair;
            for (int a = 0; a < k; ++a)
                for (int b = a; b < k; ++b) s[*slot++] += column[a] * column[b];
        }
    }
    max_diagonal_ = 0.0;
    for (int slot : diagonal_) max_diagonal_ = std::max(max_diagonal_, s[slot]);
    // a decoupled row keeps S's scale (its right-hand side is the caller's, zero for dropped rows)
    for (size_t r = 0; r < left_out_.size(); ++r)
        if (left_out_[r]) s[diagonal_[r]] = max_diagonal_ > 0.0 ? max_diagonal_ : 1.0;
    if (delta != 0.0)
        for (int slot : diagonal_) s[slot] += delta;
    ldlt_.factorize_preordered_matrix(S_);
    failed_row_ = -1;
    const double smallest = 1e-14 * max_diagonal_;
    const Eigen::VectorXd& D = ldlt_.diagonal();
    least_relative_pivot_ = 1.0;
    for (int k = 0; k < D.size(); ++k) {
        if (!(D[k] > smallest)) {
            failed_row_ = original_row_[k];
            least_relative_pivot_ = 0.0;
            return false;
        }
        least_relative_pivot_ = std::min(least_relative_pivot_, D[k] / s[diagonal_[original_row_[k]]]);
    }
    return ldlt_.info() == Eigen::Success;
}

void SparseGram::solve_once(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
    b_.noalias() = P_ * b;
    y_ = ldlt_.solve(b_);
    x.noalias() = P_.transpose() * y_;
}

void SparseGram::solve(Eigen::VectorXd& x, int refinements) {
    r_ = x;  // the right-hand side
    solve_once(r_, x);
    for (int pass = 0; pass < refinements; ++pass) {
        w_.noalias() = W_.transpose() * x;
        correction_.noalias() = W_ * w_;
        correction_ = r_ - correction_;
        solve_once(correction_, correction_);
        x += correction_;
    }
}

}  // namespace mbd
