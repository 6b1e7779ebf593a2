// Cases in threads of one process (sweep_runner.hpp).
#include <mbd/app/sweep_runner.hpp>

#include <mbd/interrupt.hpp>

#include <ctime>
#include <string>

namespace mbd {

std::optional<long> CaseDispenser::next() {
    const std::lock_guard<std::mutex> lock(mutex_);
    while (next_ < done_.size() && done_[next_]) ++next_;
    if (stopped_ || next_ >= done_.size()) return std::nullopt;
    return static_cast<long>(next_++);
}

void CaseDispenser::stop() {
    const std::lock_guard<std::mutex> lock(mutex_);
    stopped_ = true;
}

LocalWorkers::LocalWorkers(const Study& study, Registry& registry, const CaseDesign& design,
                           CaseDispenser& dispenser, int threads) {
    running_ = threads;
    for (int k = 0; k < threads; ++k)
        threads_.emplace_back([this, &study, &registry, &design, &dispenser] { work(study, registry, design, dispenser); });
}

LocalWorkers::~LocalWorkers() {
    for (std::thread& t : threads_) t.join();
}

void LocalWorkers::work(const Study& study, Registry& registry, const CaseDesign& design,
                        CaseDispenser& dispenser) {
    bool stopped = false;
    while (const std::optional<long> index = dispenser.next()) {
        try {
            CaseResult result = run_case(study, registry, design.values(*index));
            const std::lock_guard<std::mutex> lock(mutex_);
            done_.emplace_back(*index, std::move(result));
            ready_.notify_all();
        } catch (const Interrupted&) {  // the case is abandoned: it stays pending in the file
            dispenser.stop();
            stopped = true;
            break;
        }
    }
    const std::lock_guard<std::mutex> lock(mutex_);
    --running_;
    interrupted_ = interrupted_ || stopped;
    ready_.notify_all();
}

std::vector<FinishedCase> LocalWorkers::take(std::chrono::microseconds wait) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (done_.empty() && running_ > 0) ready_.wait_for(lock, wait, [this] { return !done_.empty() || running_ == 0; });
    std::vector<FinishedCase> out(std::make_move_iterator(done_.begin()), std::make_move_iterator(done_.end()));
    done_.clear();
    return out;
}

bool LocalWorkers::finished() {
    const std::lock_guard<std::mutex> lock(mutex_);
    return running_ == 0 && done_.empty();
}

bool LocalWorkers::interrupted() {
    const std::lock_guard<std::mutex> lock(mutex_);
    return interrupted_;
}

SweepProgress::SweepProgress(const SweepResults& results, bool enabled)
    : bar_(enabled), start_(results.finished()) {}

void SweepProgress::update(const SweepResults& results) {
    if (!bar_.due()) return;
    const long total = results.cases() - start_, done = results.finished() - start_;
    const double fraction = total > 0 ? static_cast<double>(done) / static_cast<double>(total) : 1.0;
    bar_.update(fraction, std::to_string(results.finished()) + " / " + std::to_string(results.cases()) + " cases, " +
                              std::to_string(results.failed()) + " failed");
}

double thread_cpu_seconds() {
    timespec now{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
    return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

SweepStats run_sweep_threads(const Study& study, Registry& registry, const CaseDesign& design,
                             SweepResults& results, const SweepOptions& options) {
    const double cpu_start = thread_cpu_seconds();
    const long finished_before = results.finished();
    CaseDispenser dispenser(results.done_cases());
    SweepProgress progress(results, options.progress);
    {
        LocalWorkers workers(study, registry, design, dispenser, options.threads);
        while (!workers.finished()) {
            for (FinishedCase& c : workers.take(std::chrono::milliseconds(100))) results.add(c.first, std::move(c.second));
            if (pending_interrupt()) dispenser.stop();
            results.flush();
            progress.update(results);
        }
    }
    progress.finish();
    if (pending_interrupt() || results.finished() < results.cases()) {
        results.flush(true);
        stop_if_interrupted();
    }
    results.commit();
    return SweepStats{results.finished() - finished_before, thread_cpu_seconds() - cpu_start};
}

}  // namespace mbd
