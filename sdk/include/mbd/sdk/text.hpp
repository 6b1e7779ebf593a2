// The one number formatter and the one time formatter for messages, logs and reports
// (core, application layer, command line and plugins alike): a message that names a
// value prints it the same way wherever it comes from.
#pragma once

#include <cstdio>
#include <string>

namespace mbd {

// A value in a message: six significant digits by default ("%.6g": 0.001, 1e-09, 3.14159,
// inf, nan); fewer where a report cell or a residual needs only its order of magnitude.
inline std::string format_number(double x, int digits = 6) {
    char buffer[48];
    std::snprintf(buffer, sizeof buffer, "%.*g", digits, x);
    return buffer;
}

// A simulated time in a message or a log line: ten significant digits ("%.10g"), enough to
// tell apart the steps of a long run.
inline std::string format_time(double t) {
    char buffer[40];
    std::snprintf(buffer, sizeof buffer, "%.10g", t);
    return buffer;
}

}  // namespace mbd
