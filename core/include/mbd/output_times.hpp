// The output times 0, h, 2h, ..., t_end of simulate, kinematics and inverse: when
// t_end is not a multiple of h (up to round-off), the last interval is shorter.
#pragma once

#include <string>

namespace mbd {

// The most rows a run writes: a step that would give more is refused rather than
// filling a disk (or, below round-off, silently writing a single row).
constexpr long kMaxOutputRows = 10'000'000;

// The number of intervals up to t_end >= 0. Throws InputError naming `step_name`
// (e.g. "--step") when h is not positive and finite or the rows would exceed
// kMaxOutputRows, and naming `end_name` when t_end is negative or not finite.
long output_intervals(double t_end, double h, const std::string& step_name = "the output step",
                      const std::string& end_name = "the end time");

}  // namespace mbd
