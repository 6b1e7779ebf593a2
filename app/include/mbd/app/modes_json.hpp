// The report of `mbd modes --json` and of Python's Model.modes(): one object (about, residual,
// coordinates, modes, ignorable, A, B; docs/user-guide.md "Modes"), so that both print the
// same numbers.
#pragma once

#include <mbd/app/json_output.hpp>
#include <mbd/modes.hpp>

#include <string>
#include <vector>

namespace mbd {

// The names of the states, in the order of A's columns: the coordinates, then each velocity
// coordinate + "_rate".
std::vector<std::string> state_names(const LinearModel& linear);

Json modes_json(const std::string& about, const LinearModel& linear, const ModeAnalysis& analysis);

const char* mode_kind(const Mode& mode);  // oscillatory, free_velocity or real

}  // namespace mbd
