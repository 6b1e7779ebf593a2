// Output times (see output_times.hpp).
#include <mbd/output_times.hpp>

#include <mbd/sdk/params.hpp>
#include <mbd/sdk/text.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace mbd {


long output_intervals(double t_end, double h, const std::string& step_name, const std::string& end_name) {
    if (!(std::isfinite(t_end) && t_end >= 0.0))
        throw InputError(end_name, "must be a finite number >= 0, got " + format_number(t_end));
    if (!(std::isfinite(h) && h > 0.0))
        throw InputError(step_name, "must be a positive finite number, got " + format_number(h));
    const double ratio = t_end / h;
    if (!(ratio < static_cast<double>(kMaxOutputRows)))
        throw InputError(step_name, format_number(h) + " up to t = " + format_time(t_end) + " gives " + format_number(ratio + 1.0) +
                                        " rows; at most " + std::to_string(kMaxOutputRows) +
                                        " are written: use a larger step (e.g. " +
                                        format_number(t_end / 1000.0) + " for 1000 rows)");
    return std::max(0L, static_cast<long>(std::ceil(ratio - 1e-9 * std::max(1.0, ratio))));
}

}  // namespace mbd
