// Failure kinds of engine messages (failure_kind.hpp).
#include <mbd/app/failure_kind.hpp>

namespace mbd {

std::string failure_kind(const std::string& m, bool assembly) {
    auto has = [&m](const char* s) { return m.find(s) != std::string::npos; };
    if (assembly) return "assembly_failure";
    if (has("step size collapse")) return "step_size_collapse";
    if (has("Newton iteration did not converge") || has("CV_CONV_FAILURE") || has("did not converge"))
        return "newton_divergence";
    if (has("mass matrix is singular")) return "singular_mass_matrix";
    if (has("redundant")) return "redundant_constraints";
    if (has("singular")) return "singular_constraints";
    if (has("initial state could not be projected") || has("could not be assembled")) return "assembly_failure";
    if (has("projection onto the constraint manifold failed")) return "projection_failure";
    // an energy gain in a conservative scene (energy_growth.hpp) is the start of a blow-up
    if (has("grew without bound") || has("total energy T + V grew") || has("non-finite") || has("diverged"))
        return "blow_up";
    if (has("maximum number of steps") || has("CV_TOO_MUCH_WORK")) return "max_steps";
    if (has("CV_ERR_FAILURE")) return "step_size_collapse";
    return "solver_failure";
}

}  // namespace mbd
