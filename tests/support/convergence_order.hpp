// The order a method shows on a sequence of runs whose step halves from one to the next:
// log2 of each ratio of successive errors, printed with the errors and asserted strictly inside
// (lo, hi). The integrator and formulation tests' convergence checks share it.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace mbd::test {

inline void expect_order_under_halving(const std::vector<double>& errors, double lo, double hi,
                                       const std::string& label) {
    for (size_t k = 1; k < errors.size(); ++k) {
        const double order = std::log2(errors[k - 1] / errors[k]);
        std::printf("%s: error %.3e -> %.3e, order %.3f\n", label.c_str(), errors[k - 1], errors[k], order);
        EXPECT_GT(order, lo) << label << ", halving " << k;
        EXPECT_LT(order, hi) << label << ", halving " << k;
    }
}

}  // namespace mbd::test
