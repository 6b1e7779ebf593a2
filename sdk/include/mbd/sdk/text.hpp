// Small text helpers shared by the plugins' messages.
#pragma once

#include <cstdio>
#include <string>

namespace mbd {

// A time for a log line or an error message: "%.10g".
inline std::string format_time(double t) {
    char buffer[40];
    std::snprintf(buffer, sizeof buffer, "%.10g", t);
    return buffer;
}

}  // namespace mbd
