// keyframe_rows (keyframes.hpp). For the anchor row a and a candidate end row j, the
// segment a..j reproduces every inner row r within tolerance e exactly when its slope
// (v_j - v_a) / (t_j - t_a) lies in [max_r (v_r - e - v_a) / (t_r - t_a),
// min_r (v_r + e - v_a) / (t_r - t_a)]: the line then passes within e of each v_r.
#include <mbd/viewer/keyframes.hpp>

#include <algorithm>
#include <limits>

namespace mbd::viewer {

std::vector<size_t> keyframe_rows(const MotionTable& table, const std::vector<KeyframeColumn>& columns) {
    const size_t rows = table.rows();
    std::vector<size_t> kept{0};
    if (rows <= 2) {
        if (rows == 2) kept.push_back(1);
        return kept;
    }
    const double inf = std::numeric_limits<double>::infinity();
    const size_t n = columns.size();
    std::vector<double> low(n, -inf), high(n, inf);  // admissible slopes of each column
    size_t anchor = 0;
    auto restart = [&](size_t row) {
        anchor = row;
        std::fill(low.begin(), low.end(), -inf);
        std::fill(high.begin(), high.end(), inf);
    };
    for (size_t j = 1; j < rows; ++j) {
        const double dt = table.at(j, 0) - table.at(anchor, 0);
        bool reaches = true;
        for (size_t c = 0; c < n && reaches; ++c) {
            const int k = columns[c].column;
            const double slope = (table.at(j, k) - table.at(anchor, k)) / dt;
            reaches = slope >= low[c] && slope <= high[c];
        }
        if (!reaches) {  // the segment ends at the row before, which starts the next one
            kept.push_back(j - 1);
            restart(j - 1);
        }
        // row j becomes an inner row of the segments that go beyond it
        const double dj = table.at(j, 0) - table.at(anchor, 0);
        for (size_t c = 0; c < n; ++c) {
            const int k = columns[c].column;
            const double v = table.at(j, k) - table.at(anchor, k), e = columns[c].tolerance;
            low[c] = std::max(low[c], (v - e) / dj);
            high[c] = std::min(high[c], (v + e) / dj);
        }
    }
    if (kept.back() != rows - 1) kept.push_back(rows - 1);
    return kept;
}

}  // namespace mbd::viewer
