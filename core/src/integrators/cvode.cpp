// SUNDIALS CVODE (Hindmarsh et al., "SUNDIALS: Suite of nonlinear and
// differential/algebraic equation solvers", ACM TOMS 31, 2005): variable-order
// (1-5), variable-step BDF with Newton iteration, a dense direct linear solver and
// CVODE's internal difference-quotient Jacobian, on the formulation's ODE.
// rtol = atol = settings.tolerance. The formulation's projection runs inside
// CVODE after each step through CVodeSetProjFn (SUNDIALS >= 5.3; Debian 12 ships
// 6.4), so the BDF history stays on the constraint manifold.
#include "common.hpp"

#include <cvode/cvode.h>
#include <cvode/cvode_proj.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <cmath>
#include <exception>

namespace mbd::integrators {
namespace {

// Everything CVODE's C callbacks need. Exceptions must not cross the C code:
// they are stored here and rethrown after CVode returns.
struct Callback {
    OdeProblem* problem = nullptr;
    Eigen::VectorXd y, ydot, projected;
    std::exception_ptr error;
    std::string message;  // the last message of CVODE's error handler
};

int rhs_callback(realtype t, N_Vector y, N_Vector ydot, void* user) {
    auto* cb = static_cast<Callback*>(user);
    const Eigen::Index n = cb->y.size();
    try {
        cb->y = Eigen::Map<const Eigen::VectorXd>(N_VGetArrayPointer(y), n);
        cb->problem->rhs(t, cb->y, cb->ydot);
        Eigen::Map<Eigen::VectorXd>(N_VGetArrayPointer(ydot), n) = cb->ydot;
        return cb->ydot.allFinite() ? 0 : 1;  // recoverable: CVODE retries with a smaller step
    } catch (...) {
        cb->error = std::current_exception();
        return -1;
    }
}

int projection_callback(realtype t, N_Vector ycur, N_Vector corr, realtype /*eps*/, N_Vector /*err*/, void* user) {
    auto* cb = static_cast<Callback*>(user);
    const Eigen::Index n = cb->y.size();
    try {
        Eigen::Map<Eigen::VectorXd> y(N_VGetArrayPointer(ycur), n);
        cb->projected = y;
        // CVODE projects before its error test, so this step may still be rejected: a time
        // just below t keeps the formulation from re-selecting here (it re-selects only at
        // the end of the step, t >= its last rhs time); integrate() re-selects after the step
        if (!cb->problem->project(std::nextafter(t, -HUGE_VAL), cb->projected)) return 1;  // recoverable
        Eigen::Map<Eigen::VectorXd>(N_VGetArrayPointer(corr), n) = cb->projected - y;
        y = cb->projected;
        return 0;
    } catch (...) {
        cb->error = std::current_exception();
        return -1;
    }
}

void error_handler(int /*code*/, const char* module, const char* function, char* msg, void* user) {
    auto* cb = static_cast<Callback*>(user);
    cb->message = std::string(module ? module : "CVODE") + "/" + (function ? function : "") + ": " + (msg ? msg : "");
}

// RAII for the SUNDIALS objects.
struct Sundials {
    SUNContext context = nullptr;
    N_Vector y = nullptr;
    SUNMatrix A = nullptr;
    SUNLinearSolver solver = nullptr;
    void* cvode = nullptr;
    ~Sundials() {
        if (cvode) CVodeFree(&cvode);
        if (solver) SUNLinSolFree(solver);
        if (A) SUNMatDestroy(A);
        if (y) N_VDestroy(y);
        if (context) SUNContext_Free(&context);
    }
};

class Cvode final : public Integrator {
public:
    explicit Cvode(const IntegratorSettings& settings) : settings_(settings) {}
    std::string name() const override { return "cvode"; }
    bool adaptive() const override { return true; }

    void integrate(OdeProblem& problem, double t0, Eigen::VectorXd& y, const std::vector<double>& output_times,
                   const OutputCallback& output, IntegratorStats& stats) override;

private:
    IntegratorSettings settings_;
};

void Cvode::integrate(OdeProblem& problem, double t0, Eigen::VectorXd& y, const std::vector<double>& output_times,
                      const OutputCallback& output, IntegratorStats& stats) {
    check_output_times(name(), t0, output_times);
    if (!(settings_.tolerance > 0.0)) throw InputError(name(), "needs a positive tolerance");
    const int n = problem.size();
    if (y.size() != n)
        throw InputError(name(), "state size " + std::to_string(y.size()) + " does not match the problem size " +
                                     std::to_string(n));
    if (output_times.empty()) return;
    const double t_end = output_times.back();
    const double eps = time_epsilon(t0, t_end);

    size_t next = 0;
    while (next < output_times.size() && output_times[next] <= t0 + eps) {
        if (output && !output(output_times[next], y)) return;
        ++next;
    }
    if (next == output_times.size()) return;

    Callback cb;
    cb.problem = &problem;
    cb.y.resize(n);
    cb.ydot.resize(n);
    cb.projected.resize(n);

    Sundials s;
    auto check = [&](int flag, const char* call) {
        if (flag < 0) {
            if (cb.error) std::rethrow_exception(cb.error);
            throw DynamicsError(t0, std::string("cvode: ") + call + " failed: " + CVodeGetReturnFlagName(flag) +
                                        (cb.message.empty() ? "" : " (" + cb.message + ")"));
        }
    };
    if (SUNContext_Create(nullptr, &s.context) != 0) throw DynamicsError(t0, "cvode: cannot create a SUNDIALS context");
    s.y = N_VNew_Serial(n, s.context);
    if (!s.y) throw DynamicsError(t0, "cvode: cannot allocate the state vector");
    Eigen::Map<Eigen::VectorXd> ymap(N_VGetArrayPointer(s.y), n);
    ymap = y;
    s.cvode = CVodeCreate(CV_BDF, s.context);
    if (!s.cvode) throw DynamicsError(t0, "cvode: CVodeCreate failed");
    check(CVodeSetErrHandlerFn(s.cvode, &error_handler, &cb), "CVodeSetErrHandlerFn");
    check(CVodeInit(s.cvode, &rhs_callback, t0, s.y), "CVodeInit");
    check(CVodeSetUserData(s.cvode, &cb), "CVodeSetUserData");
    check(CVodeSStolerances(s.cvode, settings_.tolerance, settings_.tolerance), "CVodeSStolerances");
    s.A = SUNDenseMatrix(n, n, s.context);
    s.solver = SUNLinSol_Dense(s.y, s.A, s.context);
    if (!s.A || !s.solver) throw DynamicsError(t0, "cvode: cannot create the dense linear solver");
    check(CVodeSetLinearSolver(s.cvode, s.solver, s.A), "CVodeSetLinearSolver");  // no Jacobian fn: internal DQ
    check(CVodeSetProjFn(s.cvode, &projection_callback), "CVodeSetProjFn");
    check(CVodeSetProjErrEst(s.cvode, SUNFALSE), "CVodeSetProjErrEst");
    check(CVodeSetStopTime(s.cvode, t_end), "CVodeSetStopTime");
    const double scale = std::max({std::abs(t0), std::abs(t_end), t_end - t0});
    check(CVodeSetMinStep(s.cvode, settings_.min_step * scale), "CVodeSetMinStep");
    check(CVodeSetMaxStep(s.cvode, t_end - t0), "CVodeSetMaxStep");
    if (settings_.step > 0.0) check(CVodeSetInitStep(s.cvode, settings_.step), "CVodeSetInitStep");

    auto collect = [&]() {
        long nst = 0, netf = 0, nfe = 0, nfeLS = 0, nje = 0, nni = 0, ncfn = 0;
        CVodeGetNumSteps(s.cvode, &nst);
        CVodeGetNumErrTestFails(s.cvode, &netf);
        CVodeGetNumNonlinSolvConvFails(s.cvode, &ncfn);
        CVodeGetNumRhsEvals(s.cvode, &nfe);
        CVodeGetNumLinRhsEvals(s.cvode, &nfeLS);
        CVodeGetNumJacEvals(s.cvode, &nje);
        CVodeGetNumNonlinSolvIters(s.cvode, &nni);
        stats.steps += nst;
        stats.rejected_steps += netf + ncfn;
        stats.rhs_evaluations += nfe + nfeLS;
        stats.jacobian_evaluations += nje;
        stats.newton_iterations += nni;
    };

    // A formulation that re-selects its independent coordinates in project() changes
    // the meaning of part of y (Formulation::state_redefined): the BDF history then
    // describes another state, so CVODE restarts from the current (t, y) with
    // CVodeReInit (history discarded, order 1). Steps are taken one at a time
    // (CV_ONE_STEP) to check this after every step, and each output time is a stop
    // time, so no output is interpolated across a restart.
    auto redefined = [&]() { return problem.state_redefined(); };
    redefined();  // a flag left by an earlier run does not concern this one
    long steps_before = 0;  // CVodeReInit zeroes CVODE's counters: the steps of earlier segments
    double t_cur = t0;
    auto restart = [&](double t, const Eigen::VectorXd& ynew) {
        long nst = 0;
        CVodeGetNumSteps(s.cvode, &nst);
        steps_before += nst;
        collect();
        ymap = ynew;
        check(CVodeReInit(s.cvode, t, s.y), "CVodeReInit");
        t_cur = t;
    };
    auto fail = [&](int flag, double t_reached) {
        collect();
        if (cb.error) std::rethrow_exception(cb.error);
        double t_fail = t_reached;
        CVodeGetCurrentTime(s.cvode, &t_fail);
        std::string hint;
        if (flag == CV_TOO_MUCH_WORK) hint = " (the maximum number of steps was exceeded)";
        throw DynamicsError(t_fail, "cvode failed at t = " + format_time(t_fail) + ": " + CVodeGetReturnFlagName(flag) +
                                        hint + (cb.message.empty() ? "" : ": " + cb.message));
    };

    Eigen::VectorXd yout(n);
    while (next < output_times.size()) {
        const double t_out = output_times[next];
        if (t_out > t_cur + eps) {
            check(CVodeSetStopTime(s.cvode, t_out), "CVodeSetStopTime");
            for (;;) {
                long taken = 0;
                CVodeGetNumSteps(s.cvode, &taken);
                if (steps_before + taken >= settings_.max_steps) fail(CV_TOO_MUCH_WORK, t_cur);
                double t_reached = t_cur;
                const int flag = CVode(s.cvode, t_out, s.y, &t_reached, CV_ONE_STEP);
                if (flag < 0) fail(flag, t_reached);
                t_cur = t_reached;
                const bool at_output = flag == CV_TSTOP_RETURN || t_reached >= t_out - eps;
                // the accepted step: the formulation may re-select its coordinates here
                yout = ymap;
                project_or_throw(problem, t_reached, yout);
                if (redefined()) {
                    restart(t_reached, yout);
                    if (!at_output) check(CVodeSetStopTime(s.cvode, t_out), "CVodeSetStopTime");
                }
                if (at_output) break;
                stop_if_interrupted(t_reached);  // a step boundary: SIGINT/SIGTERM/SIGHUP stop here
            }
            t_cur = t_out;
        }
        yout = ymap;
        // the output is pulled onto the manifold as well
        project_or_throw(problem, t_out, yout);
        if (redefined()) restart(t_out, yout);  // that projection re-selected: go on from it
        ++next;
        if (output && !output(t_out, yout)) {
            y = yout;
            collect();
            return;
        }
        y = yout;
    }
    collect();
}

}  // namespace

std::unique_ptr<Integrator> make_cvode(const IntegratorSettings& settings) { return std::make_unique<Cvode>(settings); }

}  // namespace mbd::integrators
