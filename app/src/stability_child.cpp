// One stability case in a forked child (run_case_isolated, mbd/app/stability.hpp): the child runs
// the case within its processor-time budget and reports its progress and outcome through a pipe,
// so a hang or a crash of the engine becomes a named outcome of the matrix, not the end of it.
#include <mbd/app/stability.hpp>

#include <mbd/app/scene_loader.hpp>
#include <mbd/interrupt.hpp>
#include <mbd/registry.hpp>
#include <mbd/scene.hpp>

#include <sys/resource.h>
#include <sys/wait.h>
#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <sstream>
#include <string>

namespace mbd {

namespace {

void write_all(int fd, const std::string& text) {
    size_t done = 0;
    while (done < text.size()) {
        const ssize_t w = write(fd, text.data() + done, text.size() - done);
        if (w <= 0) break;
        done += static_cast<size_t>(w);
    }
}

// The forked child of run_case_isolated: runs the case, writing "progress\tT\tT_END" lines
// (at most ten a second) and then its result line "KIND\tERROR\tBOUND\tTIME\tSECONDS\tMESSAGE".
[[noreturn]] void run_child(const std::string& scene, const std::string& formulation, const std::string& integrator,
                            double t_end, double cpu_limit, const SceneLoader& load, int fd) {
    CellOutcome c;
    if (cpu_limit > 0.0) {  // a run that ignores its budget (stuck in one step) ends by SIGXCPU
        const rlim_t seconds = static_cast<rlim_t>(std::ceil(cpu_limit));
        const rlimit limit{seconds, seconds + 5};
        setrlimit(RLIMIT_CPU, &limit);
    }
    auto last = std::chrono::steady_clock::now() - std::chrono::seconds(1);
    const CaseProgress report = [&](double t, double end) {
        const auto now = std::chrono::steady_clock::now();
        if (now - last < std::chrono::milliseconds(100)) return;
        last = now;
        char line[96];
        std::snprintf(line, sizeof line, "progress\t%.17g\t%.17g\n", t, end);
        write_all(fd, line);
    };
    try {
        Registry registry;
        const Scene loaded = load_with(load, scene, registry);
        c = run_case(loaded.model, registry, read_expectation(loaded), formulation, integrator, t_end, report);
    } catch (const std::exception& x) {
        c.kind = "error";
        c.message = x.what();
    } catch (const Interrupted& x) {
        _exit(x.exit_status());  // the parent stops too (interrupt.hpp)
    }
    std::string msg = c.message.substr(0, 2000);
    std::replace(msg.begin(), msg.end(), '\n', ' ');
    char head[256];
    std::snprintf(head, sizeof head, "%s\t%.17g\t%.17g\t%.17g\t%.17g\t", c.kind.c_str(), c.error, c.bound, c.time,
                  c.seconds);
    write_all(fd, head + msg + "\n");
    close(fd);
    _exit(0);
}

// What the parent reads from the child: its latest progress, and its result line.
struct ChildReport {
    double t = 0.0, t_end = 0.0;
    std::string result;

    void append(const char* data, size_t size) {
        partial_.append(data, size);
        size_t end;
        while ((end = partial_.find('\n')) != std::string::npos) {
            const std::string line = partial_.substr(0, end + 1);
            partial_.erase(0, end + 1);
            if (line.rfind("progress\t", 0) != 0) {
                result += line;
                continue;
            }
            std::istringstream in(line.substr(9));
            double time = 0.0, end_time = 0.0;
            if (in >> time >> end_time) t = time, t_end = end_time;
        }
    }

    // At the end of the pipe: a last line without its newline is part of the result.
    void end() {
        result += partial_;
        partial_.clear();
    }

    // The outcome from the result line "kind\terror\tbound\ttime\tseconds\tmessage" of a child
    // that exited with `status`; a missing line is a crash.
    void read_outcome(int status, CellOutcome& out) const {
        std::istringstream in(result);
        std::string kind, error, bound, time, seconds, message;
        if (!std::getline(in, kind, '\t') || !std::getline(in, error, '\t') || !std::getline(in, bound, '\t') ||
            !std::getline(in, time, '\t') || !std::getline(in, seconds, '\t')) {
            out.kind = "crashed";
            out.message = "the child exited without a result (status " + std::to_string(WEXITSTATUS(status)) + ")";
            return;
        }
        std::getline(in, message);
        out.kind = kind;
        out.error = std::stod(error);
        out.bound = std::stod(bound);
        out.time = std::stod(time);
        out.seconds = std::stod(seconds);
        out.message = message;
    }

private:
    std::string partial_;  // a line not yet complete
};

}  // namespace

CellOutcome run_case_isolated(const std::string& scene, const std::string& formulation, const std::string& integrator,
                              double t_end, const CaseProgress& progress, const SceneLoader& load) {
    double budget = 30.0;
    {
        Registry registry;
        budget = read_expectation(load_with(load, scene, registry)).budget;
    }
    int fds[2];
    CellOutcome out;
    if (pipe(fds) != 0) {
        out.kind = "error";
        out.message = "pipe() failed";
        return out;
    }
    std::fflush(nullptr);
    const auto start = std::chrono::steady_clock::now();
    const pid_t pid = fork();
    if (pid == 0) {
        close(fds[0]);
        run_child(scene, formulation, integrator, t_end, budget + 10.0, load, fds[1]);
    }
    close(fds[1]);
    if (pid < 0) {
        close(fds[0]);
        out.kind = "error";
        out.message = "fork() failed";
        return out;
    }
    ChildReport report;
    int status = 0;
    rusage usage{};
    bool killed = false;
    // The child ends itself by SIGXCPU past its processor budget; this wall limit only catches a child
    // that hangs without computing, so it is generous for a loaded machine.
    const double hard_limit = 20.0 * budget + 60.0;
    for (;;) {
        pollfd p{fds[0], POLLIN, 0};
        const int ready = poll(&p, 1, 100);
        if (ready > 0) {
            char buf[4096];
            const ssize_t n = read(fds[0], buf, sizeof buf);
            if (n > 0) report.append(buf, static_cast<size_t>(n));
            if (n == 0) break;  // EOF: the child closed its end (exited)
        }
        if (progress) progress(report.t, report.t_end);
        if (pending_interrupt() != 0) {  // a stop signal: end the child and stop the matrix here
            kill(pid, SIGKILL);
            close(fds[0]);
            waitpid(pid, &status, 0);
            stop_if_interrupted();
        }
        const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (t > hard_limit && !killed) {
            kill(pid, SIGKILL);
            killed = true;
        }
        if (killed && ready <= 0 && wait4(pid, &status, WNOHANG, &usage) == pid) break;
    }
    if (!killed) {
        report.end();
        wait4(pid, &status, 0, &usage);
    }
    close(fds[0]);
    out.seconds = static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
                  1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
    if (killed || (WIFSIGNALED(status) && WTERMSIG(status) == SIGXCPU)) {
        out.kind = "budget_exceeded";
        return out;
    }
    if (WIFSIGNALED(status)) {
        out.kind = "crashed";
        out.signal = WTERMSIG(status);
        return out;
    }
    report.read_outcome(status, out);
    return out;
}

}  // namespace mbd
