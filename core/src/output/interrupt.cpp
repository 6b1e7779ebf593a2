// Stop signals as a flag checked at safe points (see interrupt.hpp).
#include <mbd/interrupt.hpp>

#include <csignal>
#include <mutex>

namespace mbd {

namespace {

constexpr int kStopSignals[] = {SIGINT, SIGTERM, SIGHUP};

volatile std::sig_atomic_t g_pending = 0;

// Only async-signal-safe work here: set the flag; on a second signal, give the
// signal back its default action and raise it again.
extern "C" void note_stop_signal(int signal) {
    if (g_pending != 0) {
        std::signal(signal, SIG_DFL);
        std::raise(signal);
        return;
    }
    g_pending = signal;
}

std::mutex g_mutex;
int g_depth = 0;
struct sigaction g_previous[3];

}  // namespace

std::string Interrupted::signal_name() const {
    switch (signal_) {
        case SIGINT: return "SIGINT";
        case SIGTERM: return "SIGTERM";
        case SIGHUP: return "SIGHUP";
    }
    return "signal " + std::to_string(signal_);
}

InterruptScope::InterruptScope() {
    std::lock_guard<std::mutex> lock(g_mutex);
    if (g_depth++ > 0) return;
    g_pending = 0;
    struct sigaction action {};
    action.sa_handler = &note_stop_signal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;  // blocking reads and writes go on; the loops check the flag
    for (int k = 0; k < 3; ++k) sigaction(kStopSignals[k], &action, &g_previous[k]);
}

InterruptScope::~InterruptScope() {
    std::lock_guard<std::mutex> lock(g_mutex);
    if (--g_depth > 0) return;
    for (int k = 0; k < 3; ++k) sigaction(kStopSignals[k], &g_previous[k], nullptr);
    g_pending = 0;  // outside a scope nothing stops (library users keep their own handlers)
}

int pending_interrupt() { return g_pending; }

void stop_if_interrupted(double time) {
    if (g_pending != 0) throw Interrupted(g_pending, time);
}

}  // namespace mbd
