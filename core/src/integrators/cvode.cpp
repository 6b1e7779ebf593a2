// SUNDIALS CVODE (Hindmarsh et al., "SUNDIALS: Suite of nonlinear and
// differential/algebraic equation solvers", ACM TOMS 31, 2005): variable-order
// (1-5), variable-step BDF with Newton iteration, a dense direct linear solver (Eigen's LU,
// cvode_dense_lu.hpp) and CVODE's internal difference-quotient Jacobian, on the
// formulation's ODE.
// rtol = atol = settings.tolerance. The formulation's projection runs inside
// CVODE after each step through CVodeSetProjFn (SUNDIALS >= 5.3; Debian 12 ships
// 6.4), so the BDF history stays on the constraint manifold. That is the one projection
// of a step: only a problem that can redefine its state (OdeProblem::may_redefine_state,
// a re-selection of coordinates, which must wait until CVODE has accepted the step) is
// projected once more after it, and an event's interpolated state is projected there.
// Events (OdeProblem::event_count) are CVODE's root functions (CVodeRootInit): at a root
// CVODE returns the interpolated state there; the problem acts on the event and the run
// restarts at the root (CVodeReInit), so no step of the BDF history straddles an event.
#include "common.hpp"
#include "cvode_dense_lu.hpp"
#include "event_locator.hpp"
#include <mbd/kit/non_finite_motion.hpp>

#include <cvode/cvode.h>
#include <cvode/cvode_proj.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <cmath>
#include <exception>

namespace mbd::integrators {
namespace {

// Everything CVODE's C callbacks need. Exceptions must not cross the C code:
// they are stored here and rethrown after CVode returns.
struct Callback {
    OdeProblem* problem = nullptr;
    Eigen::VectorXd y, ydot, projected, g;
    std::exception_ptr error;
    std::string message;  // the last message of CVODE's error handler
    double tolerance = 0.0;  // rtol = atol
};

int rhs_callback(realtype t, N_Vector y, N_Vector ydot, void* user) {
    auto* cb = static_cast<Callback*>(user);
    const Eigen::Index n = cb->y.size();
    try {
        cb->y = Eigen::Map<const Eigen::VectorXd>(N_VGetArrayPointer(y), n);
        cb->problem->rhs(t, cb->y, cb->ydot);
        Eigen::Map<Eigen::VectorXd>(N_VGetArrayPointer(ydot), n) = cb->ydot;
        return cb->ydot.allFinite() ? 0 : 1;  // recoverable: CVODE retries with a smaller step
    } catch (const NonFiniteMotion&) {
        return 1;  // recoverable, as a non-finite ydot
    } catch (...) {
        cb->error = std::current_exception();
        return -1;
    }
}

// The error weights 1 / (rtol |y_i| + atol) of CVodeSStolerances, and for the problem's
// quadratures (OdeProblem::quadrature_count) a weight that leaves them out of the error test
// and of the corrector's convergence test (positive, as CVODE asks of a weight).
int error_weights(N_Vector y, N_Vector weights, void* user) {
    auto* cb = static_cast<Callback*>(user);
    const Eigen::Index n = cb->y.size(), controlled = n - cb->problem->quadrature_count();
    const Eigen::Map<const Eigen::VectorXd> values(N_VGetArrayPointer(y), n);
    Eigen::Map<Eigen::VectorXd> w(N_VGetArrayPointer(weights), n);
    // CVODE's norms are root mean squares over all n: sqrt(n / controlled) keeps the motion's
    // norms what they are without the quadratures, so the steps are those of a run without them
    const double mean_over_controlled = std::sqrt(static_cast<double>(n) / static_cast<double>(controlled));
    w.head(controlled) =
        mean_over_controlled / (cb->tolerance * values.head(controlled).array().abs() + cb->tolerance);
    w.tail(n - controlled).setConstant(1e-300);
    return 0;
}

int root_callback(realtype t, N_Vector y, realtype* g, void* user) {
    auto* cb = static_cast<Callback*>(user);
    const Eigen::Index n = cb->y.size();
    try {
        cb->y = Eigen::Map<const Eigen::VectorXd>(N_VGetArrayPointer(y), n);
        cb->problem->event_values(t, cb->y, cb->g);
        Eigen::Map<Eigen::VectorXd>(g, cb->g.size()) = cb->g;
        return 0;
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

// One run of CVODE: its SUNDIALS objects, the callback data, and the bookkeeping
// across restarts.
//
// A formulation that re-selects its independent coordinates in project() changes
// the meaning of part of y (Formulation::state_redefined): the BDF history then
// describes another state, so CVODE restarts from the current (t, y) with
// CVodeReInit (history discarded, order 1). Steps are taken one at a time
// (CV_ONE_STEP) to check this after every step, and each output time is a stop
// time, so no output is interpolated across a restart. Between steps the run keeps
// CVODE's history: a run cut into many step() calls is one CVODE run.
class CvodeRun {
public:
    CvodeRun(OdeProblem& problem, const IntegratorSettings& settings, IntegratorStats& stats, double t0)
        : problem_(problem), settings_(settings), stats_(stats), t0_(t0), t_cur_(t0) {}

    // Creates the solver for y at t0, integrating up to t_end.
    void create(const Eigen::VectorXd& y, double t_end);
    // The time CVODE has reached.
    double time() const { return t_cur_; }
    // One step (CV_ONE_STEP) toward the stop time t_stop, which it does not pass: the state
    // reached in yout (at t_stop exactly when it got there, within eps).
    void step(double t_stop, double eps, Eigen::VectorXd& yout);
    // Adds CVODE's counters since the last call (or restart) to the run's statistics.
    void collect();

private:
    Eigen::Map<Eigen::VectorXd> state() {
        return Eigen::Map<Eigen::VectorXd>(N_VGetArrayPointer(s_.y), problem_.size());
    }
    // Throws for a failed SUNDIALS call (the callbacks' own exception first).
    void check(int flag, const char* call) const;
    void restart(double t, const Eigen::VectorXd& y);
    [[noreturn]] void fail(int flag, double t_reached);
    // At a root CVODE returned at t (the state there in yout): the problem acts on the
    // events that crossed, and the run restarts at t.
    void handle_events(double t, Eigen::VectorXd& yout);
    // The state at the stop time t_stop (a step end, already on the manifold; for a problem
    // that can redefine its state, projected again: a chance to re-select).
    void output_state(double t_stop, Eigen::VectorXd& yout);

    OdeProblem& problem_;
    const IntegratorSettings& settings_;
    IntegratorStats& stats_;
    double t0_;
    Callback cb_;
    Sundials s_;
    long steps_before_ = 0;  // CVodeReInit zeroes CVODE's counters: the steps of earlier segments
    // CVODE's counters already added to the statistics since the last restart
    long collected_[7] = {0, 0, 0, 0, 0, 0, 0};
    double stop_time_ = HUGE_VAL;  // the stop time CVODE was given last
    double t_cur_;
    bool on_manifold_ = true;  // state() is a projected step end or a restart's state, not a root's interpolant
    std::vector<int> side_, crossed_, roots_;  // each event's side (+1 open, -1 closed); CVodeGetRootInfo
    EventPileUpGuard pile_up_;
};

void CvodeRun::check(int flag, const char* call) const {
    if (flag < 0) {
        if (cb_.error) std::rethrow_exception(cb_.error);
        throw DynamicsError(t0_, std::string("cvode: ") + call + " failed: " + CVodeGetReturnFlagName(flag) +
                                     (cb_.message.empty() ? "" : " (" + cb_.message + ")"));
    }
}

void CvodeRun::create(const Eigen::VectorXd& y, double t_end) {
    const int n = problem_.size();
    cb_.problem = &problem_;
    cb_.y.resize(n);
    cb_.ydot.resize(n);
    cb_.projected.resize(n);
    const double t0 = t0_;
    if (SUNContext_Create(nullptr, &s_.context) != 0)
        throw DynamicsError(t0, "cvode: cannot create a SUNDIALS context");
    s_.y = N_VNew_Serial(n, s_.context);
    if (!s_.y) throw DynamicsError(t0, "cvode: cannot allocate the state vector");
    state() = y;
    s_.cvode = CVodeCreate(CV_BDF, s_.context);
    if (!s_.cvode) throw DynamicsError(t0, "cvode: CVodeCreate failed");
    check(CVodeSetErrHandlerFn(s_.cvode, &error_handler, &cb_), "CVodeSetErrHandlerFn");
    check(CVodeInit(s_.cvode, &rhs_callback, t0, s_.y), "CVodeInit");
    check(CVodeSetUserData(s_.cvode, &cb_), "CVodeSetUserData");
    cb_.tolerance = settings_.tolerance;
    if (problem_.quadrature_count() > 0)
        check(CVodeWFtolerances(s_.cvode, &error_weights), "CVodeWFtolerances");
    else
        check(CVodeSStolerances(s_.cvode, settings_.tolerance, settings_.tolerance), "CVodeSStolerances");
    s_.A = SUNDenseMatrix(n, n, s_.context);
    s_.solver = make_dense_lu_solver(n, s_.context);
    if (!s_.A || !s_.solver) throw DynamicsError(t0, "cvode: cannot create the dense linear solver");
    check(CVodeSetLinearSolver(s_.cvode, s_.solver, s_.A), "CVodeSetLinearSolver");  // no Jacobian fn: internal DQ
    check(CVodeSetProjFn(s_.cvode, &projection_callback), "CVodeSetProjFn");
    check(CVodeSetProjErrEst(s_.cvode, SUNFALSE), "CVodeSetProjErrEst");
    check(CVodeSetStopTime(s_.cvode, t_end), "CVodeSetStopTime");
    const double scale = std::max({std::abs(t0), std::abs(t_end), t_end - t0});
    check(CVodeSetMinStep(s_.cvode, settings_.min_step * scale), "CVodeSetMinStep");
    check(CVodeSetMaxStep(s_.cvode, t_end - t0), "CVodeSetMaxStep");
    if (settings_.step > 0.0) check(CVodeSetInitStep(s_.cvode, settings_.step), "CVodeSetInitStep");
    problem_.state_redefined();  // a flag left by an earlier run does not concern this one
    const int events = problem_.event_count();
    if (events > 0) {
        cb_.g.resize(events);
        problem_.event_values(t0, y, cb_.g);
        side_.resize(events);
        for (int k = 0; k < events; ++k) side_[k] = cb_.g[k] < 0.0 ? -1 : +1;
        roots_.resize(events);
        crossed_.reserve(events);
        check(CVodeRootInit(s_.cvode, events, &root_callback), "CVodeRootInit");
        pile_up_.reset(t0);
    }
}

void CvodeRun::handle_events(double t, Eigen::VectorXd& yout) {
    check(CVodeGetRootInfo(s_.cvode, roots_.data()), "CVodeGetRootInfo");
    crossed_.clear();
    for (int k = 0; k < static_cast<int>(roots_.size()); ++k) {
        const int side = roots_[k] > 0 ? +1 : -1;  // rising: now open
        // a function that an impact left a round-off on the wrong side of zero crosses back
        // to the side the impact gave it: no event
        if (roots_[k] != 0 && side != side_[k]) {
            side_[k] = side;
            crossed_.push_back(k);
        }
    }
    if (crossed_.empty()) return;
    pile_up_.check(t, problem_, crossed_[0]);
    stats_.events += static_cast<long>(crossed_.size());
    problem_.handle_events(t, yout, crossed_, side_);
    restart(t, yout);
}

void CvodeRun::collect() {
    long now[7] = {0, 0, 0, 0, 0, 0, 0};  // nst netf ncfn nfe nfeLS nje nni
    CVodeGetNumSteps(s_.cvode, &now[0]);
    CVodeGetNumErrTestFails(s_.cvode, &now[1]);
    CVodeGetNumNonlinSolvConvFails(s_.cvode, &now[2]);
    CVodeGetNumRhsEvals(s_.cvode, &now[3]);
    CVodeGetNumLinRhsEvals(s_.cvode, &now[4]);
    CVodeGetNumJacEvals(s_.cvode, &now[5]);
    CVodeGetNumNonlinSolvIters(s_.cvode, &now[6]);
    long d[7];
    for (int k = 0; k < 7; ++k) {
        d[k] = now[k] - collected_[k];
        collected_[k] = now[k];
    }
    stats_.steps += d[0];
    stats_.rejected_steps += d[1] + d[2];
    stats_.rhs_evaluations += d[3] + d[4];
    stats_.jacobian_evaluations += d[5];
    stats_.newton_iterations += d[6];
}

void CvodeRun::restart(double t, const Eigen::VectorXd& y) {
    long nst = 0;
    CVodeGetNumSteps(s_.cvode, &nst);
    steps_before_ += nst;
    collect();
    for (long& c : collected_) c = 0;  // CVodeReInit zeroes CVODE's counters
    state() = y;
    on_manifold_ = true;
    check(CVodeReInit(s_.cvode, t, s_.y), "CVodeReInit");
    t_cur_ = t;
    stop_time_ = HUGE_VAL;  // set again before the next step
}

void CvodeRun::fail(int flag, double t_reached) {
    collect();
    if (cb_.error) std::rethrow_exception(cb_.error);
    double t_fail = t_reached;
    CVodeGetCurrentTime(s_.cvode, &t_fail);
    std::string hint;
    if (flag == CV_TOO_MUCH_WORK) hint = " (the maximum number of steps was exceeded)";
    throw DynamicsError(t_fail, "cvode failed at t = " + format_time(t_fail) + ": " + CVodeGetReturnFlagName(flag) +
                                    hint + (cb_.message.empty() ? "" : ": " + cb_.message));
}

void CvodeRun::step(double t_stop, double eps, Eigen::VectorXd& yout) {
    if (t_stop != stop_time_) {
        check(CVodeSetStopTime(s_.cvode, t_stop), "CVodeSetStopTime");
        stop_time_ = t_stop;
    }
    long taken = 0;
    CVodeGetNumSteps(s_.cvode, &taken);
    if (steps_before_ + taken >= settings_.max_steps) fail(CV_TOO_MUCH_WORK, t_cur_);
    double t_reached = t_cur_;
    const int flag = CVode(s_.cvode, t_stop, s_.y, &t_reached, CV_ONE_STEP);
    if (flag < 0) fail(flag, t_reached);
    t_cur_ = t_reached;
    on_manifold_ = flag != CV_ROOT_RETURN;
    const bool at_stop = flag == CV_TSTOP_RETURN || t_reached >= t_stop - eps;
    // CVODE forgets a stop time it reached; a restart (CVodeReInit) keeps it
    if (flag == CV_TSTOP_RETURN) stop_time_ = HUGE_VAL;
    yout = state();
    if (flag == CV_ROOT_RETURN) {
        // the state at a root is interpolated, not projected
        project_or_throw(problem_, t_reached, yout);
        problem_.state_redefined();  // the restart at the event covers a re-selection
        handle_events(t_reached, yout);
    } else if (problem_.may_redefine_state()) {
        // the accepted step: the formulation may re-select its coordinates here
        project_or_throw(problem_, t_reached, yout);
        if (problem_.state_redefined()) restart(t_reached, yout);
    }
    if (at_stop) {
        t_cur_ = t_stop;
        output_state(t_stop, yout);
        if (stop_time_ == t_stop) stop_time_ = HUGE_VAL;
    } else {
        stop_if_interrupted(t_reached);  // a step boundary: SIGINT/SIGTERM/SIGHUP stop here
    }
    collect();
}

void CvodeRun::output_state(double t_out, Eigen::VectorXd& yout) {
    yout = state();
    if (on_manifold_ && !problem_.may_redefine_state()) return;
    project_or_throw(problem_, t_out, yout);
    if (problem_.state_redefined()) restart(t_out, yout);  // that projection re-selected: go on from it
}

class Cvode final : public AdaptiveIntegrator {
public:
    using AdaptiveIntegrator::AdaptiveIntegrator;

    void begin(OdeProblem& problem, double t0, const Eigen::VectorXd& y0, double t_end,
               IntegratorStats& stats) override {
        require_adaptive_start(name(), settings_, problem, y0);
        run_.reset();
        t_ = t0;
        y_ = y0;
        eps_ = time_epsilon(t0, t_end);
        if (problem.size() == 0) return;  // every motion prescribed (a fully driven tree): nothing to integrate
        run_ = std::make_unique<CvodeRun>(problem, settings_, stats, t0);
        run_->create(y0, std::max(t_end, t0 + eps_));
    }
    bool step(double t_stop, StepOutputs* /*outputs: the steps end on each*/) override {
        if (!run_) {
            if (y_.size() != 0) throw InputError(name(), "step() before begin()");
            t_ = t_stop;  // nothing to integrate
            return true;
        }
        run_->step(t_stop, eps_, y_);
        t_ = run_->time();
        return true;
    }
    double time() const override { return t_; }
    const Eigen::VectorXd& state() const override { return y_; }

private:
    std::unique_ptr<CvodeRun> run_;
    double t_ = 0.0, eps_ = 0.0;
    Eigen::VectorXd y_;
};

}  // namespace

std::unique_ptr<Integrator> make_cvode(const IntegratorSettings& settings) { return std::make_unique<Cvode>(settings); }

}  // namespace mbd::integrators
