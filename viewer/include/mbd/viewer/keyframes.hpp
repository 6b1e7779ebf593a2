// Keyframe reduction of a result for the browser viewer: the rows that linear
// interpolation needs to reproduce every row of the chosen columns within a tolerance.
#pragma once

#include <mbd/viewer/motion_table.hpp>

#include <cstddef>
#include <vector>

namespace mbd::viewer {

struct KeyframeColumn {
    int column = 0;          // in the table
    double tolerance = 0.0;  // largest allowed |interpolated - value| at any row
};

// The rows (ascending; the first and the last always among them) such that, for every
// listed column, the straight line between consecutive kept rows passes within the
// column's tolerance of the value at every row in between. Greedy and exact: a segment
// is extended while one line through all the tolerance bands of its inner rows exists
// ("swinging door"), which costs one pass over the table.
std::vector<size_t> keyframe_rows(const MotionTable& table, const std::vector<KeyframeColumn>& columns);

}  // namespace mbd::viewer
