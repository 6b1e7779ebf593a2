// The statics result at the configuration the continuation reached: limits put
// exactly on their bounds, angles reported nearest to the start, the residual of
// the equilibrium equations (checked independently of Ipopt), what went wrong when
// it is not an equilibrium, and its stability.
#pragma once

#include "evaluator.hpp"

#include <IpIpoptApplication.hpp>

#include <mbd/kit/statics.hpp>

#include <string>
#include <vector>

namespace mbd::ipopt_plugin {

// The configuration reported nearest to the start: planar angles theta_start +
// wrap(theta - theta_start) (wrap to (-pi, pi]), Euler parameters with the sign
// of the start's. Kept unwrapped when that would change a constraint (a driver on
// an unwrapped angle) or a limited joint coordinate: then the path-continuous
// angles are the ones the equations hold for.
void wrap_angles(System& sys, Evaluator& ev, const State& start, const StaticsOptions& opt, State& state);

// Interior-point iterates stop a barrier distance (~tol / nu) inside an active
// limit. Newton steps on the square system [C; s_a - bound; Q - J^T lambda -
// J_a^T nu_a] = 0 (active limits as equalities) put them on it exactly.
void polish(System& sys, Evaluator& ev, State& state, Eigen::VectorXd& lambda, Eigen::VectorXd& nu,
            const std::vector<JointLimit>& limits);

// The residual of the equilibrium equations at res.state with res.lambda and
// res.limit_multipliers: max |C|, max |Q - J^T lambda - J_s^T nu| and the limit
// violation. Sets res.residual and res.limit_active.
struct EquilibriumResidual {
    double c_max = 0.0, r_max = 0.0, bound_violation = 0.0;
    double q_scale = 1.0;     // 1 + max |Q|
    std::vector<int> active;  // the limits at a bound
};
EquilibriumResidual measure_equilibrium(System& sys, Evaluator& ev, StaticsResult& res, const StaticsOptions& opt);

// Why a solve ended without an equilibrium, in words (ctol: the assembly tolerance on |C|).
std::string failure_message(Ipopt::ApplicationReturnStatus status, const StaticsResult& res,
                            const EquilibriumResidual& r, double ctol, const std::string& callback_error);

// Reduced Hessian of the potential on the tangent space of the active constraints:
// K = sym(-dQ/dq) + sym(d(J^T lambda + J_s^T nu)/dq), Z^T K Z with Z a null-space basis.
// Sets res.stability, res.tangent_eigenvalues and res.tangent_dimension.
void assess_stability(System& sys, Evaluator& ev, StaticsResult& res, const StaticsOptions& opt,
                      const std::vector<int>& active);

}  // namespace mbd::ipopt_plugin
