// Stopping a long run cleanly on SIGINT, SIGTERM or SIGHUP.
//
// While an InterruptScope is alive, those signals only set a flag (nothing else
// happens in the handler). Long loops (the integrators at every step boundary,
// kinematics at every output time, bench and stability between runs) call
// stop_if_interrupted(), which throws Interrupted there, after the current step
// or row is complete: the output files are then closed with whole rows only
// (output_file.hpp) and `mbd` exits with 128 + the signal number. A second
// signal while the first is still pending ends the process at once (the default
// action), for a run that no longer reaches a step boundary.
#pragma once

#include <cmath>
#include <string>

namespace mbd {

// Thrown at a safe point after a stop signal. It is deliberately not a
// std::exception: code that turns failures into a reported outcome (a bench row
// marked "failed", a stability cell) must not swallow the user's request to stop.
class Interrupted {
public:
    Interrupted(int signal, double time) : signal_(signal), time_(time) {}
    int signal() const { return signal_; }
    double time() const { return time_; }   // the simulated time reached, NaN when there is none
    std::string signal_name() const;        // "SIGINT", "SIGTERM", "SIGHUP"
    int exit_status() const { return 128 + signal_; }  // the shell's convention: 130, 143, 129

private:
    int signal_;
    double time_;
};

// Catches SIGINT, SIGTERM and SIGHUP for its lifetime (nested scopes share one
// installation) and restores the previous handlers afterwards; a signal still
// pending then is forgotten (the Interrupted it caused is already on its way).
class InterruptScope {
public:
    InterruptScope();
    ~InterruptScope();
    InterruptScope(const InterruptScope&) = delete;
    InterruptScope& operator=(const InterruptScope&) = delete;
};

// The pending stop signal, 0 when none.
int pending_interrupt();

// Throws Interrupted when a stop signal is pending; `time` is the simulated time reached.
void stop_if_interrupted(double time = NAN);

}  // namespace mbd
