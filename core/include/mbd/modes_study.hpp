// The modes of a scene (issue 17) as `mbd modes` and Python's Model.modes() compute them: the
// reference state (the statics plugin's equilibrium, or the scene's initial state taken as a
// steady motion), the linearisation about it and its modes. One function, so that the command
// and the Python module give the same numbers to the bit.
#pragma once

#include <mbd/linearisation.hpp>
#include <mbd/modes.hpp>

#include <string>

namespace mbd {

class Model;
class Registry;

struct ModesStudyOptions {
    std::string about = "statics";    // "statics" or "initial"
    double residual_tolerance = 1e-8;  // largest independent acceleration accepted at the reference
    std::string solver = "ipopt";     // the statics plugin type (about "statics")
    int statics_iterations = 500;     // its iteration limit
};

struct ModesStudy {
    bool statics_converged = true;  // false: no modes; statics_message says why
    std::string statics_message;
    LinearModel linear;
    ModeAnalysis analysis;
};

// Throws InputError for an `about` other than statics/initial, KinematicsError for a scene
// that cannot be linearised (require_linearisable, require_freedom: before any statics) or
// whose reference accelerates more than residual_tolerance.
ModesStudy study_modes(const Model& model, Registry& registry, const ModesStudyOptions& options);

}  // namespace mbd
