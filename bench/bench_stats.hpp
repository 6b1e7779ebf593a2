// Statistics shared by the rhs benchmarks: the median of repeated timings, the
// least-squares slope of log(time) against log(size) (the empirical complexity exponent),
// and the median time of one call of a cheap function.
#pragma once

#include <algorithm>
#include <chrono>
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

// Median time of one call of `call`, over batches sized to take about a millisecond each
// (at least 5 and at most 31 batches, or 2 s), after 5 warm-up calls.
template <class Call>
double median_seconds_per_call(Call&& call) {
    for (int k = 0; k < 5; ++k) call();
    using clock = std::chrono::steady_clock;
    int batch = 1;
    for (;;) {
        const auto t0 = clock::now();
        for (int k = 0; k < batch; ++k) call();
        if (clock::now() - t0 > std::chrono::microseconds(1000) || batch >= (1 << 20)) break;
        batch *= 2;
    }
    std::vector<double> times;
    const auto start = clock::now();
    while (times.size() < 31 && (times.size() < 5 || clock::now() - start < std::chrono::seconds(2))) {
        const auto t0 = clock::now();
        for (int k = 0; k < batch; ++k) call();
        times.push_back(std::chrono::duration<double>(clock::now() - t0).count() / batch);
    }
    return median(times);
}
