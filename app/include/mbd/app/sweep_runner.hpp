// Running the cases of a sweep in threads of one process (docs/sweep.md): one Model (the
// study's base scene) shared by every thread; each case builds its own changed Model and runs
// on its own Data (model_system.hpp). Threads take the next unfinished case as they become
// free (a dispenser, not fixed blocks); the calling thread records every result, flushes the
// results file and draws the progress bar. The MPI master (sweep_mpi.hpp) uses the same
// dispenser and local threads.
#pragma once

#include <mbd/app/case_record.hpp>
#include <mbd/app/study.hpp>
#include <mbd/app/study_design.hpp>
#include <mbd/app/study_case.hpp>
#include <mbd/app/sweep_results.hpp>
#include <mbd/progress_bar.hpp>

#include <chrono>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>
#include <thread>
#include <utility>
#include <vector>

namespace mbd {

// The cases still to run (those not done at the start), handed out one at a time in ascending
// order to whoever asks (thread-safe); one bit per case, no list of them.
class CaseDispenser {
public:
    explicit CaseDispenser(std::vector<bool> done) : done_(std::move(done)) {}
    std::optional<long> next();
    void stop();  // hand out nothing more (a stop signal)

private:
    std::mutex mutex_;
    std::vector<bool> done_;
    std::size_t next_ = 0;
    bool stopped_ = false;
};

// `threads` threads running cases from a dispenser until it is empty.
class LocalWorkers {
public:
    LocalWorkers(const Study& study, Registry& registry, const CaseDesign& design,
                 CaseDispenser& dispenser, int threads);
    ~LocalWorkers();  // joins (the dispenser must be empty or stopped)
    LocalWorkers(const LocalWorkers&) = delete;
    LocalWorkers& operator=(const LocalWorkers&) = delete;

    // The cases finished since the last call; waits up to `wait` when there is none yet.
    std::vector<FinishedCase> take(std::chrono::microseconds wait);
    // Every thread has ended (and take() has returned everything).
    bool finished();
    // A thread stopped by a stop signal (Interrupted) in the middle of a case.
    bool interrupted();

private:
    void work(const Study& study, Registry& registry, const CaseDesign& design,
              CaseDispenser& dispenser);

    std::mutex mutex_;
    std::condition_variable ready_;
    std::deque<FinishedCase> done_;
    int running_ = 0;
    bool interrupted_ = false;
    std::vector<std::thread> threads_;
};

// The recording thread's progress bar (progress_bar.hpp): the fraction of this run's cases
// done (a resumed run counts from where it resumed, so the time left is this run's) and the
// count of finished and failed cases.
class SweepProgress {
public:
    SweepProgress(const SweepResults& results, bool enabled);
    void update(const SweepResults& results);
    void finish() { bar_.finish(); }

private:
    ProgressBar bar_;
    long start_;
};

struct SweepOptions {
    int threads = 1;
    bool progress = true;
};

// What the recording thread (the master) cost: its CPU time over the run, which is the
// per-case overhead that bounds the scaling (docs/sweep.md, "Efficiency").
struct SweepStats {
    long cases_run = 0;
    double recorder_cpu_seconds = 0.0;
};

// CPU time of the calling thread.
double thread_cpu_seconds();

// Runs every pending case with `options.threads` threads, recording each in `results`; commits
// the file when all are done. A stop signal ends the run after the cases in progress are
// abandoned: the file keeps every finished case and Interrupted is thrown.
SweepStats run_sweep_threads(const Study& study, Registry& registry, const CaseDesign& design,
                             SweepResults& results, const SweepOptions& options);

}  // namespace mbd
