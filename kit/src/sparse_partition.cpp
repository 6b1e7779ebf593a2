// The sparse coordinate partition: see sparse_partition.hpp.
#include <mbd/kit/sparse_partition.hpp>

#include <algorithm>
#include <cmath>
#include <functional>

namespace mbd {

namespace {

// the row being reduced: add `value` at column c, queueing c's pivot step if it has one.
// A retired column (see the header) is dropped: it can no longer be a pivot.
void accumulate(SparsePartitionWorkspace& ws, int c, double value) {
    if (ws.excluded(c)) return;
    if (ws.retired(c)) {
        ws.dropped = true;
        return;
    }
    if (!ws.present[c]) {
        ws.present[c] = 1;
        ws.pattern.push_back(c);
        ws.work[c] = 0.0;
        const int step = ws.step_of_column[c];
        if (step >= 0 && !ws.queued[step]) {
            ws.queued[step] = 1;
            ws.heap.push_back(step);
            std::push_heap(ws.heap.begin(), ws.heap.end(), std::greater<int>());
        }
    }
    ws.work[c] += value;
}

// Row r of J reduced by every pivot row before it, in pivot order: pivot row s holds no
// column of a pivot before s, so applying it can only queue later pivots.
void reduce_row(SparsePartitionWorkspace& ws, int r, const CoordinatePartition& out) {
    ws.current_row = r;
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(ws.rows, r); it; ++it)
        accumulate(ws, static_cast<int>(it.col()), it.value());
    while (!ws.heap.empty()) {
        std::pop_heap(ws.heap.begin(), ws.heap.end(), std::greater<int>());
        const int s = ws.heap.back();
        ws.heap.pop_back();
        ws.queued[s] = 0;
        const int column = out.dependent[s];
        const double f = ws.work[column] / ws.pivot[s];
        ws.work[column] = 0.0;
        if (f == 0.0) continue;
        for (int e = ws.u_start[s]; e < ws.u_start[s + 1]; ++e) accumulate(ws, ws.u_column[e], -f * ws.u_value[e]);
    }
}

// the preferred pivot column of the reduced row (see the header), or -1 when it is redundant
int choose_pivot(const SparsePartitionWorkspace& ws, double threshold, double floor) {
    double amax = 0.0;
    for (int c : ws.pattern)
        if (ws.step_of_column[c] < 0) amax = std::max(amax, std::abs(ws.work[c]));
    if (!(amax > floor) || amax == 0.0) return -1;
    int best = -1;
    for (int c : ws.pattern) {
        if (ws.step_of_column[c] >= 0 || !(std::abs(ws.work[c]) >= threshold * amax)) continue;
        if (best < 0 || ws.late[c] < ws.late[best] || (ws.late[c] == ws.late[best] && c < best)) best = c;
    }
    return best;
}

// The elimination; with `retire`, columns are retired as the header says. Returns false when,
// retiring, a row was found redundant after entries had been dropped (then only the exact
// elimination can tell whether it is).
bool eliminate(const Eigen::SparseMatrix<double>& J, double threshold, double rank_tolerance,
               const std::vector<int>& last, bool retire, SparsePartitionWorkspace& ws, CoordinatePartition& out) {
    const int m = static_cast<int>(J.rows()), n = static_cast<int>(J.cols());
    ws.last_row.assign(n, retire ? -1 : m);
    if (retire)
        for (int c = 0; c < n; ++c)
            for (Eigen::SparseMatrix<double>::InnerIterator it(J, c); it; ++it)
                ws.last_row[c] = std::max(ws.last_row[c], static_cast<int>(it.row()));
    ws.dropped = false;
    ws.work.setZero(n);
    ws.present.assign(n, 0);
    ws.late.assign(n, 0);
    for (int c : last)
        if (c >= 0 && c < n) ws.late[c] = 1;
    ws.step_of_column.assign(n, -1);
    ws.queued.clear();
    ws.heap.clear();
    ws.u_start.assign(1, 0);
    ws.u_column.clear();
    ws.u_value.clear();
    ws.pivot.clear();
    out.rank = 0;
    out.dependent.clear();
    out.independent.clear();
    out.rows.clear();
    out.redundant.clear();
    double scale = 0.0;
    for (int e = 0; e < J.nonZeros(); ++e) scale = std::max(scale, std::abs(J.valuePtr()[e]));
    const double floor = rank_tolerance * scale;
    double pmin = 0.0, pmax = 0.0;
    for (int r = 0; r < m; ++r) {
        ws.pattern.clear();
        reduce_row(ws, r, out);
        const int pc = out.rank < std::min(m, n) ? choose_pivot(ws, threshold, floor) : -1;
        if (pc < 0) {
            if (ws.dropped) return false;
            out.redundant.push_back(r);
        } else {
            const int step = out.rank++;
            const double p = ws.work[pc];
            out.rows.push_back(r);
            out.dependent.push_back(pc);
            ws.pivot.push_back(p);
            ws.queued.push_back(0);
            ws.step_of_column[pc] = step;
            for (int c : ws.pattern)
                if (ws.step_of_column[c] < 0 && ws.work[c] != 0.0) {
                    ws.u_column.push_back(c);
                    ws.u_value.push_back(ws.work[c]);
                }
            ws.u_start.push_back(static_cast<int>(ws.u_column.size()));
            pmin = step == 0 ? std::abs(p) : std::min(pmin, std::abs(p));
            pmax = std::max(pmax, std::abs(p));
        }
        for (int c : ws.pattern) {
            ws.present[c] = 0;
            ws.work[c] = 0.0;
        }
    }
    for (int c = 0; c < n; ++c)
        if (ws.step_of_column[c] < 0) out.independent.push_back(c);
    out.pivot_ratio = out.rank ? pmin / pmax : 1.0;
    return true;
}

// ws.rows = J by rows. Eigen's conversion builds a new matrix (it allocates): while J keeps
// the pattern of the last conversion, its values are copied into place instead.
void copy_by_rows(const Eigen::SparseMatrix<double>& J, SparsePartitionWorkspace& ws) {
    const size_t nnz = static_cast<size_t>(J.nonZeros());
    const int* outer = J.outerIndexPtr();
    const int* inner = J.innerIndexPtr();
    const bool same = J.isCompressed() && ws.rows.rows() == J.rows() && ws.rows.cols() == J.cols() &&
                      ws.slot.size() == nnz && std::equal(inner, inner + nnz, ws.pattern_inner.begin()) &&
                      std::equal(outer, outer + J.outerSize() + 1, ws.pattern_outer.begin());
    if (!same) {
        ws.rows = J;
        ws.rows.makeCompressed();
        ws.slot.assign(nnz, 0);
        if (J.isCompressed()) {
            ws.pattern_outer.assign(outer, outer + J.outerSize() + 1);
            ws.pattern_inner.assign(inner, inner + nnz);
        } else {
            ws.pattern_outer.clear();
            ws.pattern_inner.clear();
        }
        // columns ascending visit each row's entries in its (ascending) storage order
        std::vector<int> cursor(ws.rows.outerIndexPtr(), ws.rows.outerIndexPtr() + ws.rows.rows());
        int e = 0;
        for (int c = 0; c < J.outerSize(); ++c)
            for (Eigen::SparseMatrix<double>::InnerIterator it(J, c); it; ++it, ++e) ws.slot[e] = cursor[it.row()]++;
        if (!J.isCompressed()) ws.slot.clear();  // no fast path for an uncompressed J
        return;
    }
    const double* values = J.valuePtr();
    double* into = ws.rows.valuePtr();
    for (size_t e = 0; e < nnz; ++e) into[ws.slot[e]] = values[e];
}

}  // namespace

void partition_sparse(const Eigen::SparseMatrix<double>& J, double threshold, double rank_tolerance,
                      const std::vector<int>& last, SparsePartitionWorkspace& ws, CoordinatePartition& out) {
    copy_by_rows(J, ws);
    ws.allowed.clear();
    // a re-selection (threshold 1) looks for the best pivots among every column: exactly
    const bool retire = threshold < 1.0;
    if (!eliminate(J, threshold, rank_tolerance, last, retire, ws, out))
        eliminate(J, threshold, rank_tolerance, last, false, ws, out);
}

double dependent_pivot_ratio(const Eigen::SparseMatrix<double>& J, const CoordinatePartition& p, double rank_tolerance,
                             SparsePartitionWorkspace& ws, CoordinatePartition& scratch) {
    copy_by_rows(J, ws);
    ws.allowed.assign(J.cols(), 0);
    for (int c : p.dependent) ws.allowed[c] = 1;
    eliminate(J, 1.0, rank_tolerance, {}, false, ws, scratch);
    ws.allowed.clear();
    return scratch.rank == p.rank ? scratch.pivot_ratio : 0.0;
}

CoordinatePartition partition_sparse(const Eigen::SparseMatrix<double>& J, double threshold, double rank_tolerance,
                                     const std::vector<int>& last) {
    SparsePartitionWorkspace ws;
    CoordinatePartition out;
    partition_sparse(J, threshold, rank_tolerance, last, ws, out);
    return out;
}

}  // namespace mbd
