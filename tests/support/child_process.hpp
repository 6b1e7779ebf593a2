// Tests that run mbd as a child process they watch while it runs: started in the background,
// waited for a condition, stopped, and measured (peak memory from wait4's ru_maxrss).
#pragma once

#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <thread>

namespace mbd::test {

// Starts `command` through /bin/sh with its output discarded; the child's pid.
inline pid_t spawn_quiet(const std::string& command) {
    const pid_t pid = fork();
    if (pid == 0) {
        execl("/bin/sh", "sh", "-c", ("exec " + command + " > /dev/null 2>&1").c_str(), static_cast<char*>(nullptr));
        _exit(127);
    }
    return pid;
}

// `mbd ARGUMENTS` as a command for spawn_quiet, with AddressSanitizer's quarantine of freed
// blocks (256 MB by default) kept small in the child, so that its peak memory measures mbd, not
// the sanitizer (ignored in a build without it; the rest of ASAN_OPTIONS is kept).
inline std::string mbd_command(const std::string& executable, const std::string& arguments) {
    return "env ASAN_OPTIONS=\"${ASAN_OPTIONS}:quarantine_size_mb=1\" " + executable + " " + arguments;
}

// Waits for `done` up to a generous wall time (a loaded or sanitizer build); false if it never
// held or the child ended first.
template <class Condition>
bool wait_until(Condition done, pid_t child) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(2);
    while (std::chrono::steady_clock::now() < deadline) {
        if (done()) return true;
        int status = 0;
        if (waitpid(child, &status, WNOHANG) == child) return false;  // it ended first
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
}

// Waits for the child to end, expects it to exit with `expected_exit`; its peak resident
// memory in kB.
inline long wait_peak_kb(pid_t child, int expected_exit, const std::string& what) {
    int status = 0;
    rusage usage{};
    EXPECT_EQ(wait4(child, &status, 0, &usage), child);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == expected_exit) << what << ": status " << status;
    return usage.ru_maxrss;
}

}  // namespace mbd::test
