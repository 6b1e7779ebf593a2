// Statics with Ipopt (plugin kind "statics", type "ipopt"). See docs/statics.md.
//
// The solve from a start: choose the objective (potential when all forces are
// conservative at rest, else virtual work; statics_nlp.hpp), run the trust-region
// continuation (continuation.hpp), then check and describe the equilibrium it
// reached (equilibrium.hpp). The default objective searches for a stable
// equilibrium (relaxation.hpp).
#include "continuation.hpp"
#include "equilibrium.hpp"
#include "evaluator.hpp"
#include "ipopt_common.hpp"
#include "relaxation.hpp"

#include <mbd/kit/statics.hpp>

#include <IpIpoptApplication.hpp>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>

namespace mbd::ipopt_plugin {
namespace {

// True when Q(q, v = 0) = -grad V at q0 and at a perturbed configuration (checked
// along a few random directions): the forces are conservative at rest (damping
// does not count), so the potential can be minimised.
bool conservative_at_rest(System& sys, const State& start) {
    const int nv = sys.nv();
    std::mt19937 rng(12345);
    std::normal_distribution<double> normal;
    auto random_vector = [&] {
        Eigen::VectorXd d(nv);
        for (int i = 0; i < nv; ++i) d[i] = normal(rng);
        return d;
    };
    Eigen::VectorXd Q;
    for (int point = 0; point < 2; ++point) {
        State s = start;
        s.v.setZero(nv);
        if (point == 1) sys.advance_positions(s.q, 1e-2 * random_vector());
        sys.generalized_forces(s, Q);
        for (int trial = 0; trial < 3; ++trial) {
            const Eigen::VectorXd d = random_vector().normalized();
            const double h = 1e-6;
            State p = s, m = s;
            sys.advance_positions(p.q, h * d);
            sys.advance_positions(m.q, -h * d);
            const double dV = (sys.potential_energy(p) - sys.potential_energy(m)) / (2 * h);
            const double work = Q.dot(d);
            if (std::abs(dV + work) > 1e-6 * (std::abs(dV) + Q.norm()) + 1e-9) return false;
        }
    }
    return true;
}

// Minimum-norm least-squares lambda from J^T lambda = Q (starting multipliers).
Eigen::VectorXd initial_multipliers(System& sys, const State& s) {
    const int mc = sys.constraint_rows(true);
    if (mc == 0) return Eigen::VectorXd();
    ConstraintValues cv;
    sys.constraints(s, cv, true);
    Eigen::VectorXd Q;
    sys.generalized_forces(s, Q);
    if (sys.nv() <= 1500) {
        const Eigen::MatrixXd Jt = Eigen::MatrixXd(cv.J).transpose();
        return Jt.completeOrthogonalDecomposition().solve(Q);
    }
    Eigen::SparseMatrix<double> A = cv.J * cv.J.transpose();
    for (int i = 0; i < mc; ++i) A.coeffRef(i, i) += 1e-12 * (1.0 + A.coeffRef(i, i));
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(A);
    return ldlt.solve(cv.J * Q);
}

// The objective actually used: as asked, or for "auto" the potential when the forces are conservative at rest.
bool use_potential(System& sys, const State& at, const StaticsOptions& opt) {
    if (opt.objective == "potential") return true;
    if (opt.objective == "virtual-work") return false;
    return sys.conservative() || conservative_at_rest(sys, at);
}

Ipopt::SmartPtr<Ipopt::IpoptApplication> make_application(const StaticsOptions& opt, bool potential) {
    Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
    app->Options()->SetIntegerValue("print_level", opt.print_level);
    app->Options()->SetStringValue("sb", "yes");
    app->Options()->SetNumericValue("tol", opt.tolerance);
    app->Options()->SetNumericValue("constr_viol_tol", opt.tolerance);
    app->Options()->SetNumericValue("dual_inf_tol", opt.tolerance);
    app->Options()->SetNumericValue("compl_inf_tol", std::max(opt.tolerance, 1e-12));
    app->Options()->SetIntegerValue("max_iter", opt.max_iterations);
    app->Options()->SetStringValue("mu_strategy", "adaptive");
    app->Options()->SetStringValue("hessian_approximation",
                                   potential && opt.hessian != "limited-memory" ? "exact" : "limited-memory");
    if (const char* check = std::getenv("MBD_IPOPT_DERIVATIVE_TEST"))  // debugging aid: first-order, second-order
        app->Options()->SetStringValue("derivative_test", check);
    return app;
}

class IpoptStatics final : public StaticsSolver {
public:
    // The default objective means "the equilibrium the mechanism settles in": when the solve
    // from the start fails or ends at an unstable equilibrium, the over-damped path from the
    // start is followed to a stable one (relaxation.hpp) and the solve repeated from there.
    // An explicit objective keeps the nearest equilibrium, stable or not. Dense, without
    // joint limits (nv <= 600, no limits).
    StaticsResult solve(System& sys, const State& start, const StaticsOptions& opt) override {
        StaticsOptions assessed = opt;
        assessed.analyse_stability = true;  // the search needs the verdict
        const bool search = opt.objective == "auto" && opt.limits.empty() && sys.nv() <= 600;
        StaticsResult first = solve_from(sys, start, search ? assessed : opt);
        if (!search || (first.converged && first.stability != "unstable")) return reported(first, opt);

        Evaluator ev(sys, opt.time, {});
        const IncrementGeometry geo = increment_geometry(sys, start.q);
        Eigen::VectorXd unit(sys.nv());
        for (int i = 0; i < sys.nv(); ++i) unit[i] = geo.rotation(i) ? 1.0 : geo.length;
        Relaxation relaxation(sys, ev, unit, opt.stability_tolerance);
        const RelaxationResult relaxed = relaxation.run(start.q);
        if (opt.print_level > 0)
            std::printf("mbd statics: the solve from the start %s; relaxation: %s after %d iteration(s), %d move(s) "
                        "off an unstable equilibrium\n",
                        first.converged ? "ended at an unstable equilibrium" : "failed",
                        relaxed.converged ? "converged" : "did not converge", relaxed.iterations,
                        relaxed.displacements);
        if (!relaxed.converged) return reported(first, opt);
        State from = start;
        from.q = relaxed.q;
        StaticsResult second = solve_from(sys, from, assessed);
        if (!second.converged || second.stability == "unstable") return reported(first, opt);
        second.iterations += first.iterations;
        wrap_angles(sys, ev, start, opt, second.state);  // reported nearest to the original start
        return reported(second, opt);
    }

private:
    static StaticsResult reported(StaticsResult res, const StaticsOptions& opt) {
        if (!opt.analyse_stability && res.converged) {
            res.stability = "not assessed";
            res.tangent_eigenvalues.resize(0);
            res.tangent_dimension = 0;
        }
        return res;
    }

    StaticsResult solve_from(System& sys, const State& start, const StaticsOptions& opt) {
        StaticsResult res;
        res.state = start;
        res.state.t = opt.time;
        res.state.v = Eigen::VectorXd::Zero(sys.nv());
        const bool potential = use_potential(sys, res.state, opt);
        res.objective = potential ? "potential" : "virtual-work";

        std::vector<int> limit_joints;
        for (const auto& l : opt.limits) limit_joints.push_back(l.joint);
        Evaluator ev(sys, opt.time, limit_joints);

        const Eigen::VectorXd lambda0 = potential ? Eigen::VectorXd() : initial_multipliers(sys, res.state);
        const std::lock_guard<std::mutex> one_ipopt_at_a_time(ipopt_lock());
        Ipopt::SmartPtr<Ipopt::IpoptApplication> app = make_application(opt, potential);
        const Ipopt::ApplicationReturnStatus status = app->Initialize();
        if (status != Ipopt::Solve_Succeeded) {
            res.status = status_name(status);
            res.message = "Ipopt could not be initialised";
            return res;
        }
        Continuation continuation(sys, ev, opt, potential, start.q, lambda0);
        const ContinuationResult run = continuation.run(*app);
        res.status = status_name(run.status);
        res.iterations = run.iterations;
        if (opt.print_level > 0)
            std::printf("mbd statics: %d accepted step(s), %d rejected (left the start's assembly branch), "
                        "final box factor %g\n", run.segments, run.rejected, run.factor);
        if (!run.nlp->finalized) {
            res.message = "Ipopt stopped without a result (" + res.status + ")" +
                          (run.nlp->callback_error.empty() ? std::string() : ": " + run.nlp->callback_error);
            return res;
        }
        if (!run.failure.empty()) {
            res.state.q = run.centre;  // the last configuration reached on the start's branch
            wrap_angles(sys, ev, start, opt, res.state);
            res.message = run.failure;
            res.stability = "not assessed";
            return res;
        }
        read_equilibrium(sys, ev, start, opt, potential, run, res);
        const EquilibriumResidual r = measure_equilibrium(sys, ev, res, opt);
        res.converged = finished(run.status) && res.residual <= 1e-6 * r.q_scale;
        if (!res.converged) {
            res.message = failure_message(run.status, res, r, run.ctol, run.nlp->callback_error);
            res.stability = "not assessed";
            return res;
        }
        if (opt.analyse_stability)
            assess_stability(sys, ev, res, opt, r.active);
        else
            res.stability = "not assessed";
        return res;
    }

    // The equilibrium and its multipliers from the last solve (limits polished onto
    // their bounds, angles nearest to the start).
    static void read_equilibrium(System& sys, Evaluator& ev, const State& start, const StaticsOptions& opt,
                                 bool potential, const ContinuationResult& run, StaticsResult& res) {
        const int nv = sys.nv(), mc = sys.constraint_rows(true), nl = static_cast<int>(opt.limits.size());
        const StaticsNLP& nlp = *run.nlp;
        res.state.q = run.centre;
        if (!finished(run.status)) {  // report the failing solve's own point
            res.state.q = run.centre;
            sys.advance_positions(res.state.q, nlp.x_final.head(nv));
        }
        Eigen::VectorXd nu = Eigen::VectorXd::Zero(nl);
        if (potential) {
            res.lambda = nlp.g_multipliers.head(mc);
            nu = nlp.g_multipliers.segment(mc, nl);
        } else {
            res.lambda = nlp.x_final.segment(nv, mc);
            for (int k = 0; k < nl; ++k) nu[k] = nlp.x_final[nv + mc + nl + k] - nlp.x_final[nv + mc + k];
        }
        if (nl > 0 && nv <= 600) polish(sys, ev, res.state, res.lambda, nu, opt.limits);
        wrap_angles(sys, ev, start, opt, res.state);
        res.limit_multipliers = nu;
    }
};

std::unique_ptr<StaticsSolver> make_ipopt_statics(const StaticsSpec&) { return std::make_unique<IpoptStatics>(); }

}  // namespace
}  // namespace mbd::ipopt_plugin

MBD_STATICS_PLUGIN(ipopt, mbd::ipopt_plugin::make_ipopt_statics)
