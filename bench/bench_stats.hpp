// Statistics shared by the rhs benchmarks: the median of repeated timings, and the
// least-squares slope of log(time) against log(size) (the empirical complexity exponent).
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

inline double median(std::vector<double> x) {
    std::sort(x.begin(), x.end());
    return x[x.size() / 2];
}

inline double slope(const std::vector<double>& n, const std::vector<double>& t) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    const double m = static_cast<double>(n.size());
    for (size_t k = 0; k < n.size(); ++k) {
        const double x = std::log(n[k]), y = std::log(t[k]);
        sx += x, sy += y, sxx += x * x, sxy += x * y;
    }
    return (m * sxy - sx * sy) / (m * sxx - sx * sx);
}
