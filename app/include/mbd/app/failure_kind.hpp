// The failure kind of an engine message (step_size_collapse, newton_divergence, ...): the
// names of the stability matrix (docs/stability.md), also the `failure` column of a sweep.
#pragma once

#include <string>

namespace mbd {

// `assembly`: the run failed while assembling its initial state (always assembly_failure).
std::string failure_kind(const std::string& message, bool assembly);

}  // namespace mbd
