// Statistics shared by the rhs benchmarks: the median of repeated timings, the
// least-squares slope of log(time) against log(size) (the empirical complexity exponent),
// and the median time of one call of a cheap function.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cmath>
#include <ctime>
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

// The CPU time of the calling thread, as a std::chrono clock: on a machine shared by many
// processes the wall clock measures the scheduler (a benchmark given 3% of a core reads 30x).
struct thread_cpu_clock {
    using duration = std::chrono::nanoseconds;
    using rep = duration::rep;
    using period = duration::period;
    using time_point = std::chrono::time_point<thread_cpu_clock>;
    static constexpr bool is_steady = true;
    static time_point now() {
        timespec ts;
        clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
        return time_point(duration(static_cast<rep>(ts.tv_sec) * 1000000000 + ts.tv_nsec));
    }
};

// Median time of one call of `call`, over batches sized to take about a millisecond each
// (at least 5 and at most 31 batches, or 2 s), after 5 warm-up calls; by the wall clock unless
// `clock` is thread_cpu_clock.
template <class Call, class clock = std::chrono::steady_clock>
double median_seconds_per_call(Call&& call, clock = {}) {
    // MBD_BENCH_CALLS=N: exactly N calls after the warm-up, for instruction counts (callgrind) that
    // do not depend on the machine's speed; two counts N1 < N2 give the cost of one call
    if (const char* fixed = std::getenv("MBD_BENCH_CALLS")) {
        const int n = std::atoi(fixed);
        for (int k = 0; k < 5; ++k) call();
        const auto t0 = clock::now();
        for (int k = 0; k < n; ++k) call();
        return std::chrono::duration<double>(clock::now() - t0).count() / std::max(n, 1);
    }
    for (int k = 0; k < 5; ++k) call();
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
