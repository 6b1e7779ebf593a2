// A sweep across MPI ranks (docs/sweep.md, "Across machines"): `mpirun -np N mbd sweep ...`.
// Rank 0 is the master and the only writer: its main thread hands out case indices on request
// and records the results, while its own local threads run cases too. Every other rank is a
// worker that asks for the next case whenever it finishes one (dynamic distribution, with one
// case in hand ahead so that a worker never waits for the master's answer). Every rank reads
// the study and computes the same design, so only case indices and results travel.
//
// A process not started by an MPI launcher (no OMPI_COMM_WORLD_SIZE or PMI_SIZE in its
// environment) runs in-process without initialising MPI.
#pragma once

#include <mbd/app/study.hpp>
#include <mbd/app/study_design.hpp>
#include <mbd/app/sweep_results.hpp>
#include <mbd/app/sweep_runner.hpp>

#include <memory>
#include <vector>

namespace mbd {

struct MpiRole {
    bool launched = false;   // started by mpirun: MPI is initialised (finalised with the last copy)
    int rank = 0, size = 1;
    std::shared_ptr<void> session;
};

MpiRole mpi_role();

// Rank 0: runs the pending cases of `results` on its local threads and on the workers,
// records them and commits the file; a stop signal flushes the file, then aborts the job
// (MPI_Abort) with Interrupted's exit status.
SweepStats run_sweep_master(const Study& study, Registry& registry, const CaseDesign& design,
                            SweepResults& results, const SweepOptions& options);

// Ranks > 0: cases on request until the master says stop; returns the exit status (0).
int run_sweep_worker(const Study& study, Registry& registry, const CaseDesign& design);

// Rank 0 failed before the cases began (bad input): tell every worker to stop.
void release_workers(const MpiRole& role);

}  // namespace mbd
