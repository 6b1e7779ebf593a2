#include "sparse_gram.hpp"

#include <Eigen/OrderingMethods>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace mbd {

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
    const int nvb = mass_inverse.velocities_per_body();
    std::fill(W_.valuePtr(), W_.valuePtr() + W_.nonZeros(), 0.0);
    left_out_.assign(W_.rows(), 0);
    if (left_out) left_out_ = *left_out;
    const int* outer = W_.outerIndexPtr();
    const int* inner = W_.innerIndexPtr();
    double* w = W_.valuePtr();
    for (int c = 0; c < J.outerSize(); ++c) {
        const int b = c / nvb, i = c % nvb;
        const auto& L = mass_inverse.factor(b);
        // columns b nvb .. c in one group: a row sits at the same place in each of them, found
        // by walking column c's rows along J's (both sorted), not searched per entry
        const bool grouped = group_of_column_[b * nvb] == group_of_column_[c];
        int place = outer[c];
        for (Eigen::SparseMatrix<double>::InnerIterator it(J, c); it; ++it) {
            const int row = static_cast<int>(it.row());
            if (left_out_[row]) continue;
            if (grouped) {
                while (place < outer[c + 1] && inner[place] < row) ++place;
                if (place == outer[c + 1] || inner[place] != row) entry_of_W(row, c);  // throws: outside the pattern
                const int offset = place - outer[c];
                for (int j = 0; j <= i; ++j)
                    if (L(i, j) != 0.0) w[outer[b * nvb + j] + offset] += it.value() * L(i, j);
            } else {
                for (int j = 0; j <= i; ++j) {
                    const double l = L(i, j);
                    if (l != 0.0) entry_of_W(row, b * nvb + j) += it.value() * l;
                }
            }
        }
    }
}

void SparseGram::fill(const Eigen::SparseMatrix<double>& J) {
    std::fill(W_.valuePtr(), W_.valuePtr() + W_.nonZeros(), 0.0);
    left_out_.assign(W_.rows(), 0);
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

    // S's upper pattern: every pair of rows that share a column, and the diagonal
    std::vector<Eigen::Triplet<double>> s_entries;
    for (int r = 0; r < rows; ++r) s_entries.emplace_back(r, r, 1.0);
    for (int c = 0; c < cols; ++c)
        for (Eigen::SparseMatrix<double>::InnerIterator a(W_, c); a; ++a)
            for (Eigen::SparseMatrix<double>::InnerIterator b(W_, c); b; ++b)
                if (a.row() <= b.row()) s_entries.emplace_back(a.row(), b.row(), 1.0);
    Eigen::SparseMatrix<double> S(rows, rows);
    S.setFromTriplets(s_entries.begin(), s_entries.end());
    S.makeCompressed();
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
    for (int k = 0; k < S.nonZeros(); ++k) S.valuePtr()[k] = k + 1;
    S_.resize(rows, rows);
    S_.selfadjointView<Eigen::Upper>() = S.selfadjointView<Eigen::Upper>().twistedBy(P_);
    S_.makeCompressed();
    std::vector<int> moved(S.nonZeros(), -1);
    for (int k = 0; k < S_.nonZeros(); ++k) moved[static_cast<int>(S_.valuePtr()[k]) - 1] = k;

    groups_.clear();
    pair_slots_.clear();
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
    const int* slot = pair_slots_.data();
    for (const ColumnGroup& g : groups_) {
        const double* block = w + outer[g.first_column];  // rows x columns, column-major
        const int k = g.rows;
        for (int a = 0; a < k; ++a)
            for (int b = a; b < k; ++b) {
                double sum = 0.0;
                for (int c = 0; c < g.columns; ++c) sum += block[c * k + a] * block[c * k + b];
                s[*slot++] += sum;
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
