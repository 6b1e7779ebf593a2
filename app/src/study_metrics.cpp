// Row-by-row reductions of a case's result table (study_metrics.hpp).
#include <mbd/app/study_metrics.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace mbd {

MetricAccumulator::MetricAccumulator(const std::vector<StudyMetric>& metrics,
                                     const std::vector<std::string>& table_columns) {
    for (const StudyMetric& m : metrics) {
        const auto it = std::find(table_columns.begin(), table_columns.end(), m.column);
        if (it == table_columns.end())
            throw std::logic_error("metric " + m.name + ": column not in the case's table");
        reductions_.push_back(m.reduction);
        source_.push_back(static_cast<std::size_t>(it - table_columns.begin()));
    }
    value_.assign(metrics.size(), 0.0);
}

void MetricAccumulator::add(const std::vector<double>& row) {
    for (std::size_t k = 0; k < reductions_.size(); ++k) {
        const double x = row[source_[k]];
        double& v = value_[k];
        switch (reductions_[k]) {
        case Reduction::Final: v = x; break;
        case Reduction::Max: v = rows_ == 0 ? x : std::max(v, x); break;
        case Reduction::Min: v = rows_ == 0 ? x : std::min(v, x); break;
        case Reduction::Rms: v += x * x; break;
        }
    }
    ++rows_;
}

std::vector<double> MetricAccumulator::values() const {
    if (rows_ == 0) throw std::logic_error("MetricAccumulator: no rows");
    std::vector<double> out = value_;
    for (std::size_t k = 0; k < out.size(); ++k)
        if (reductions_[k] == Reduction::Rms) out[k] = std::sqrt(out[k] / static_cast<double>(rows_));
    return out;
}

}  // namespace mbd
