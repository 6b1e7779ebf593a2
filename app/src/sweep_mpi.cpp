// Master/worker distribution of a sweep over MPI ranks (sweep_mpi.hpp), with the MPI C API.
//
// Messages (MPI_COMM_WORLD):
//   worker -> master  kReady  int: how many cases it asks for (at the start: 2, one ahead)
//   worker -> master  kResult bytes: a finished case (encode_case, case_record.hpp); asks for one more
//   master -> worker  kCase   long: the case index to run
//   master -> worker  kStop   nothing: no case is left, finish the ones in hand and end
// Only rank 0's main thread calls MPI (MPI_THREAD_FUNNELED); its local threads take cases
// from the same dispenser the workers' requests draw from.
#include <mbd/app/sweep_mpi.hpp>

#include <mbd/app/case_record.hpp>

#include <mbd/interrupt.hpp>

#include <mpi.h>

#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <stdexcept>
#include <string>

namespace mbd {

namespace {

constexpr int kReady = 1, kResult = 2, kCase = 3, kStop = 4;
// Cases a worker holds beyond the one it runs: enough to cover the master's longest pause between
// serving (kMasterPause) for short cases, few enough that the last cases still spread evenly.
constexpr int kCasesAhead = 8;
// How long the master waits for its own threads' results when no worker message came: its
// polling is CPU taken from the cases on its rank (2 ms: about 1% of a core for the polls).
constexpr std::chrono::microseconds kMasterPause(2000);

bool launched_by_mpi() { return std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr || std::getenv("PMI_SIZE") != nullptr; }

class Session {
public:
    Session() {
        int provided = 0;
        if (MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS)
            throw std::runtime_error("MPI_Init_thread failed");
        if (provided < MPI_THREAD_FUNNELED) {
            MPI_Finalize();
            throw std::runtime_error("the MPI library does not allow threads (MPI_THREAD_FUNNELED)");
        }
    }
    ~Session() { MPI_Finalize(); }
};

// ---- the master's side

class Master {
public:
    Master(int ranks, CaseDispenser& dispenser)
        : dispenser_(dispenser), outstanding_(static_cast<std::size_t>(ranks), 0),
          stopped_(static_cast<std::size_t>(ranks), false) {
        stopped_[0] = true;  // rank 0 runs its cases in its own threads
    }

    // Every message waiting now, results into `results`; false when there was none.
    bool serve(SweepResults& results) {
        bool any = false;
        for (;;) {
            int waiting = 0;
            MPI_Status status;
            MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &waiting, &status);
            if (!waiting) return any;
            any = true;
            int size = 0;
            MPI_Get_count(&status, MPI_BYTE, &size);
            std::vector<char> bytes(static_cast<std::size_t>(size));
            MPI_Recv(bytes.data(), size, MPI_BYTE, status.MPI_SOURCE, status.MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            const int worker = status.MPI_SOURCE;
            if (status.MPI_TAG == kReady) {
                int count = 0;
                std::memcpy(&count, bytes.data(), sizeof count);
                for (int k = 0; k < count; ++k) assign(worker);
            } else if (status.MPI_TAG == kResult) {
                FinishedCase c = decode_case(bytes.data(), bytes.size());
                --outstanding_[static_cast<std::size_t>(worker)];
                results.add(c.first, std::move(c.second));
                assign(worker);
            }
        }
    }

    // Every worker told to stop and every case it was given recorded.
    bool workers_done() const {
        for (std::size_t w = 0; w < stopped_.size(); ++w)
            if (!stopped_[w] || outstanding_[w] > 0) return false;
        return true;
    }

private:
    void assign(int worker) {
        const auto w = static_cast<std::size_t>(worker);
        if (stopped_[w]) return;
        if (const std::optional<long> index = dispenser_.next()) {
            const long value = *index;
            MPI_Send(&value, sizeof value, MPI_BYTE, worker, kCase, MPI_COMM_WORLD);
            ++outstanding_[w];
        } else {
            MPI_Send(nullptr, 0, MPI_BYTE, worker, kStop, MPI_COMM_WORLD);
            stopped_[w] = true;
        }
    }

    CaseDispenser& dispenser_;
    std::vector<int> outstanding_;
    std::vector<bool> stopped_;
};

}  // namespace

MpiRole mpi_role() {
    MpiRole role;
    if (!launched_by_mpi()) return role;
    role.session = std::make_shared<Session>();
    role.launched = true;
    MPI_Comm_rank(MPI_COMM_WORLD, &role.rank);
    MPI_Comm_size(MPI_COMM_WORLD, &role.size);
    return role;
}

SweepStats run_sweep_master(const Study& study, Registry& registry, const CaseDesign& design,
                            SweepResults& results, const SweepOptions& options) {
    const double cpu_start = thread_cpu_seconds();
    const long finished_before = results.finished();
    int ranks = 1;
    MPI_Comm_size(MPI_COMM_WORLD, &ranks);
    CaseDispenser dispenser(results.done_cases());
    SweepProgress progress(results, options.progress);
    Master master(ranks, dispenser);
    {
        LocalWorkers local(study, registry, design, dispenser, options.threads);
        while (!local.finished() || !master.workers_done()) {
            const bool served = master.serve(results);
            for (FinishedCase& c : local.take(served ? std::chrono::microseconds(0) : kMasterPause))
                results.add(c.first, std::move(c.second));
            if (const int signal = pending_interrupt()) {
                // the workers are not waited for: what is recorded is kept, the rest runs on --resume
                dispenser.stop();
                results.flush(true);
                progress.finish();
                std::fprintf(stderr, "mbd: error: stopped by signal %d; '%s' holds the %ld of %ld cases finished; "
                                     "continue with --resume\n",
                             signal, results.partial_path().c_str(), results.finished(), results.cases());
                MPI_Abort(MPI_COMM_WORLD, 128 + signal);
            }
            results.flush();
            progress.update(results);
        }
    }
    progress.finish();
    results.commit();
    return SweepStats{results.finished() - finished_before, thread_cpu_seconds() - cpu_start};
}

int run_sweep_worker(const Study& study, Registry& registry, const CaseDesign& design) {
    const int ahead = kCasesAhead;
    MPI_Send(&ahead, sizeof ahead, MPI_BYTE, 0, kReady, MPI_COMM_WORLD);
    std::deque<long> in_hand;
    bool stopped = false;
    auto receive = [&](bool wait) {
        for (;;) {
            int waiting = 0;
            MPI_Status status;
            if (wait) MPI_Probe(0, MPI_ANY_TAG, MPI_COMM_WORLD, &status), waiting = 1;
            else MPI_Iprobe(0, MPI_ANY_TAG, MPI_COMM_WORLD, &waiting, &status);
            if (!waiting) return;
            long index = 0;
            MPI_Recv(&index, sizeof index, MPI_BYTE, 0, status.MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            if (status.MPI_TAG == kCase) in_hand.push_back(index);
            else stopped = true;
            wait = false;
        }
    };
    for (;;) {
        receive(in_hand.empty() && !stopped);
        if (in_hand.empty()) {
            if (stopped) return 0;
            continue;
        }
        const long index = in_hand.front();
        in_hand.pop_front();
        const std::vector<char> bytes =
            encode_case(index, run_case(study, registry, design.values(index)));
        MPI_Send(bytes.data(), static_cast<int>(bytes.size()), MPI_BYTE, 0, kResult, MPI_COMM_WORLD);
    }
}

void release_workers(const MpiRole& role) {
    if (!role.launched || role.rank != 0) return;
    for (int w = 1; w < role.size; ++w) MPI_Send(nullptr, 0, MPI_BYTE, w, kStop, MPI_COMM_WORLD);
}

}  // namespace mbd
