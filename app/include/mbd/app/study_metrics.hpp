// The metrics of one case (docs/sweep.md, "Metrics"): each a reduction (final, max, min or
// RMS over the rows) of a column of the case's result table, accumulated row by row so that no
// time history need be kept.
#pragma once

#include <mbd/app/study.hpp>

#include <string>
#include <vector>

namespace mbd {

class MetricAccumulator {
public:
    // `table_columns`: the columns of the rows add() will be given (a subset of Study::columns
    // holding every metric's column).
    MetricAccumulator(const std::vector<StudyMetric>& metrics, const std::vector<std::string>& table_columns);

    void add(const std::vector<double>& row);
    // One value per metric, in the study's order; throws std::logic_error before any row.
    std::vector<double> values() const;
    long rows() const { return rows_; }

private:
    std::vector<Reduction> reductions_;
    std::vector<std::size_t> source_;    // the row index each metric reads
    std::vector<double> value_;          // running final / max / min / sum of squares
    long rows_ = 0;
};

}  // namespace mbd
