// The report of `mbd statics --json` and of Python's Model.statics(): one object (keys in
// docs/statics.md); NaN (a driver without a multiplier, a joint without a coordinate) and
// infinite limits become null when printed by json_text (json_output.hpp).
#pragma once

#include <mbd/app/json_output.hpp>
#include <mbd/statics_analysis.hpp>

#include <vector>

namespace mbd {

Json statics_json(const Model& model, const StaticsReport& report, const std::vector<JointLimit>& limits);

}  // namespace mbd
