// The statics interface: static equilibrium of a System (plugin kind "statics"),
// book Sec. 5.6 (virtual work) and Sec. 6.14 (Eq. 6.171: C(q) = 0, C_q^T lambda = Q).
//
// Unknowns: position increments x (size nv, velocity layout) from the assembled
// start q0, q(x) = q0 (+) x with System::advance_positions (spatial bodies:
// dR and a body-frame rotation vector, so the Euler parameters stay unit and no
// normalisation row is needed), plus the multipliers lambda of every
// constraint row (joints, then drivers) and of the active joint limits.
// See docs/statics.md for the method, objectives and the stability test.
#pragma once

#include <mbd/sdk/params.hpp>
#include <mbd/kit/plugin.hpp>
#include <mbd/kit/system.hpp>

#include <Eigen/Core>

#include <memory>
#include <string>
#include <vector>

namespace mbd {

// A bound lo <= s(q) <= hi on a 1-DOF joint's coordinate (scene key `limits`).
struct JointLimit {
    int joint = -1;        // index into System::joint()
    double lo = 0.0;
    double hi = 0.0;
    std::string where;     // file:line, for messages
};

struct StaticsOptions {
    double time = 0.0;                  // drivers are evaluated at this time
    std::string objective = "auto";     // "auto" | "potential" | "virtual-work"
    std::string hessian = "exact";      // "exact" | "limited-memory" (potential objective only)
    double tolerance = 1e-10;           // on the equilibrium residual (max |C|, |Q - J^T lambda|)
    int max_iterations = 500;
    double stability_tolerance = 1e-8;  // eigenvalues of the reduced Hessian within +-tol: neutral
    bool analyse_stability = true;
    int print_level = 0;                // Ipopt's print_level (0: silent)
    std::vector<JointLimit> limits;
};

struct StaticsResult {
    bool converged = false;
    std::string status;          // Ipopt's status ("Solve_Succeeded", ...), or what failed
    std::string message;         // on failure: what failed, in words
    int iterations = 0;
    std::string objective;       // the objective actually used: "potential" or "virtual-work"
    double residual = 0.0;       // max(max |C|, max |Q - J^T lambda - J_L^T nu|) at the result
    State state;                 // the equilibrium (t = options.time, v = 0)
    Eigen::VectorXd lambda;      // multipliers of every constraint row (joints, then drivers)
    Eigen::VectorXd limit_multipliers;  // nu per limit (0 when inactive); reaction -J_s^T nu
    std::vector<bool> limit_active;
    std::string stability;       // "stable" | "unstable" | "neutral" | "not assessed"
    Eigen::VectorXd tangent_eigenvalues;  // of the reduced Hessian (dense analysis), ascending
    int tangent_dimension = 0;   // dimension of the constraint tangent space
};

class MBD_SDK_API StaticsSolver {
public:
    virtual ~StaticsSolver() = default;
    // Solve from `start` (assembled; t = options.time). Never throws for a
    // solver failure: converged = false with status and message set.
    virtual StaticsResult solve(System& system, const State& start, const StaticsOptions& options) = 0;
};

struct StaticsSpec {
    std::string name;   // as selected
    std::string type;   // e.g. "ipopt"
    Params params;
};

using StaticsFactory = std::unique_ptr<StaticsSolver>(const StaticsSpec& spec);

}  // namespace mbd

#define MBD_STATICS_PLUGIN(type, factory) MBD_REGISTER_KIT_PLUGIN(statics, type, factory)
