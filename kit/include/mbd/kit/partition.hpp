// Coordinate partitioning of a constraint Jacobian (Shabana, Computational Dynamics,
// Sec. 2.5 Ex. 2.12, Sec. 5.2 and Sec. 6.5 "Identification of the system degrees of
// freedom"): Gaussian elimination with column interchanges on J (m x n) finds its rank,
// the pivot columns (the DEPENDENT coordinates, J_d nonsingular), the remaining
// INDEPENDENT columns, the pivot rows, and the rows that reduce to zero (redundant
// constraints, book L8314). Header-only so that every analysis selects the same way.
//
// Pivot choice (threshold complete pivoting): at each elimination step the largest
// remaining entry |a|max is found; the columns are then scanned in preference order and
// the first column whose largest remaining entry is at least `threshold * |a|max` is the
// pivot column (its largest entry, partial row pivoting, is the pivot). threshold = 1 is
// strict complete ("full") pivoting (book L1439); the default 0.1 (the usual threshold of
// sparse LU codes) keeps the natural column order unless that pivot is poor, which
// reproduces the book's hand elimination of Ex. 2.12 (dependent {x1, x3}) and keeps a
// selection stable from one configuration to the next. Elimination stops when the largest
// remaining entry is below rank_tolerance times the largest entry of J.
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace mbd {

struct CoordinatePartition {
    int rank = 0;
    std::vector<int> dependent;    // pivot columns, in pivot order (size rank)
    std::vector<int> independent;  // the other columns, ascending
    std::vector<int> rows;         // pivot rows, in pivot order (size rank): the rows kept
    std::vector<int> redundant;    // rows that reduced to zero (dependent on the kept rows), ascending
    double pivot_ratio = 1.0;      // smallest / largest pivot magnitude (1 when rank 0)
};

// Scratch of the elimination, reused from call to call: once it has seen matrices of a
// size, a partition of that size allocates nothing (nor does `out`, whose lists keep their
// capacity).
struct PartitionWorkspace {
    Eigen::MatrixXd a;  // the matrix being eliminated
    std::vector<char> row_used, col_used, late;
    std::vector<int> order;
};

// Sizes `ws` and `out` for partitions of m x n matrices up front (in bind()), so that even
// the first partition made during a run (a re-selection) allocates nothing.
inline void reserve_partition(int m, int n, PartitionWorkspace& ws, CoordinatePartition& out) {
    ws.a.resize(m, n);
    ws.row_used.reserve(m);
    ws.col_used.reserve(n);
    ws.late.reserve(n);
    ws.order.reserve(n);
    out.dependent.reserve(std::min(m, n));
    out.rows.reserve(std::min(m, n));
    out.independent.reserve(n);
    out.redundant.reserve(m);
}

// The elimination of the header comment on ws.a (overwritten), into `out`. `last`: columns
// to consider only after every other column (e.g. the current independent set, to keep it
// independent when it is still acceptable).
inline void partition_workspace_matrix(double threshold, double rank_tolerance, const std::vector<int>& last,
                                       PartitionWorkspace& ws, CoordinatePartition& out) {
    Eigen::MatrixXd& a = ws.a;
    const int m = static_cast<int>(a.rows()), n = static_cast<int>(a.cols());
    ws.row_used.assign(m, 0);
    ws.col_used.assign(n, 0);
    ws.late.assign(n, 0);
    ws.order.clear();
    ws.order.reserve(n);
    for (int c : last)
        if (c >= 0 && c < n) ws.late[c] = 1;
    for (int c = 0; c < n; ++c)
        if (!ws.late[c]) ws.order.push_back(c);
    for (int c = 0; c < n; ++c)
        if (ws.late[c]) ws.order.push_back(c);
    std::vector<char>&row_used = ws.row_used, &col_used = ws.col_used;
    const double scale = m && n ? a.cwiseAbs().maxCoeff() : 0.0;
    out.rank = 0;
    out.dependent.clear();
    out.independent.clear();
    out.rows.clear();
    out.redundant.clear();
    out.dependent.reserve(std::min(m, n));
    out.rows.reserve(std::min(m, n));
    out.independent.reserve(n);
    out.redundant.reserve(m);
    double pmin = 0.0, pmax = 0.0;
    for (int step = 0; step < std::min(m, n); ++step) {
        double amax = 0.0;
        for (int r = 0; r < m; ++r)
            if (!row_used[r])
                for (int c = 0; c < n; ++c)
                    if (!col_used[c]) amax = std::max(amax, std::abs(a(r, c)));
        if (!(amax > rank_tolerance * scale) || amax == 0.0) break;
        int pr = -1, pc = -1;
        for (int c : ws.order) {
            if (col_used[c]) continue;
            int best = -1;
            double value = 0.0;
            for (int r = 0; r < m; ++r)
                if (!row_used[r] && std::abs(a(r, c)) > value) value = std::abs(a(r, c)), best = r;
            if (best >= 0 && value >= threshold * amax) {
                pr = best;
                pc = c;
                break;
            }
        }
        const double pivot = a(pr, pc);
        row_used[pr] = col_used[pc] = 1;
        out.rows.push_back(pr);
        out.dependent.push_back(pc);
        pmin = step == 0 ? std::abs(pivot) : std::min(pmin, std::abs(pivot));
        pmax = std::max(pmax, std::abs(pivot));
        for (int r = 0; r < m; ++r) {
            if (row_used[r] || a(r, pc) == 0.0) continue;
            const double f = a(r, pc) / pivot;
            a.row(r) -= f * a.row(pr);
            a(r, pc) = 0.0;
        }
    }
    out.rank = static_cast<int>(out.dependent.size());
    for (int c = 0; c < n; ++c)
        if (!col_used[c]) out.independent.push_back(c);
    for (int r = 0; r < m; ++r)
        if (!row_used[r]) out.redundant.push_back(r);
    out.pivot_ratio = out.rank ? pmin / pmax : 1.0;
}

// The partition of J into `out`, with caller-provided scratch (see PartitionWorkspace).
inline void partition_coordinates(const Eigen::MatrixXd& J, double threshold, double rank_tolerance,
                                  const std::vector<int>& last, PartitionWorkspace& ws, CoordinatePartition& out) {
    ws.a = J;
    partition_workspace_matrix(threshold, rank_tolerance, last, ws, out);
}

// The partition of J, allocating its own scratch (for code off the evaluation path).
inline CoordinatePartition partition_coordinates(const Eigen::MatrixXd& J, double threshold = 0.1,
                                                 double rank_tolerance = 1e-10,
                                                 const std::vector<int>& last = {}) {
    PartitionWorkspace ws;
    CoordinatePartition out;
    partition_coordinates(J, threshold, rank_tolerance, last, ws, out);
    return out;
}

// "N redundant constraint row(s) dropped: <names>", for the log line a formulation
// writes when its partition drops rows; describe_row(r) names row r.
template <class DescribeRow>
std::string redundant_rows_message(const CoordinatePartition& partition, DescribeRow describe_row) {
    std::string rows;
    for (int r : partition.redundant) rows += (rows.empty() ? "" : ", ") + describe_row(r);
    return std::to_string(partition.redundant.size()) + " redundant constraint row" +
           (partition.redundant.size() == 1 ? "" : "s") + " dropped: " + rows;
}

}  // namespace mbd
