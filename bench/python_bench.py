#!/usr/bin/env python3
"""The Python module's costs (docs/benchmarks.md, "Python"): run it on a quiet machine with

    /usr/bin/python3 bench/python_bench.py [--build BUILD_DIR] [--rounds N]

1. Threads: 8 independent simulations of one Model (chain-50, embedding + dopri5, 8 initial
   speeds) one after another and through a ThreadPoolExecutor of as many threads as the
   process may use cores; the median over interleaved rounds of serial / parallel wall time
   (the two halves of a round are seconds apart, so a shared machine's slow and fast spells
   mostly cancel in the ratio). Target: >= 1.7 on 2 cores. The parallel results are checked
   bit for bit against the serial ones. On a machine others load, the ratio says little (with
   the kernel's autogroup scheduling, the threads of one session share one session's share of
   the cores); the check that the engine runs without the GIL is printed too: the main thread
   goes on running Python while another thread simulates.
2. Overhead: a Python call model.simulate(...) on the A01 pendulum (scenes/bench/a01-pendulum.yaml
   with its bench settings, t_end 100 s, rows every 0.5 s, augmented + dopri5 at each of its
   tolerances) against the engine's own simulate() on the same settings with nothing
   collected, as CPU time of the calling thread (which runs the engine), so that the load of
   other processes counts as little as it can: the time the call spends outside the engine
   plus the cost of collecting the rows, as a share of the engine's run. Target: < 5 %.
The load average (uptime) is printed before and after: on a busy machine the ratio of part 1
reads low.
"""

import argparse
import concurrent.futures
import os
import pathlib
import statistics
import sys
import threading
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]


def load_average():
    return "load average %.2f, %.2f, %.2f" % os.getloadavg()


def thread_speedup(mbd, rounds, np):
    model = mbd.load(ROOT / "scenes" / "bench" / "chain-50.yaml")
    v0 = model.initial_state()[1]
    speeds = [1.0 + 0.1 * k for k in range(8)]

    def run(speed):
        return model.simulate(1.0, formulation="embedding", tol=1e-6, output_step=0.01, v0=v0 * speed)

    workers = len(os.sched_getaffinity(0))
    ratios, serial_times, parallel_times = [], [], []
    for _ in range(rounds):
        began = time.perf_counter()
        serial = [run(s) for s in speeds]
        serial_times.append(time.perf_counter() - began)
        began = time.perf_counter()
        with concurrent.futures.ThreadPoolExecutor(workers) as pool:
            parallel = list(pool.map(run, speeds))
        parallel_times.append(time.perf_counter() - began)
        ratios.append(serial_times[-1] / parallel_times[-1])
        for a, b in zip(serial, parallel):
            if not np.array_equal(a.data.view(np.uint64), b.data.view(np.uint64)):
                sys.exit("a parallel run differs from its serial run")
    ratio = statistics.median(ratios)
    print(f"threads: 8 simulations of chain-50 (embedding + dopri5, t_end 1 s), {workers} worker threads, "
          f"{rounds} rounds")
    print(f"  serial   median {statistics.median(serial_times):.3f} s")
    print(f"  parallel median {statistics.median(parallel_times):.3f} s")
    print(f"  speed-up median {ratio:.2f}x (rounds: {', '.join(f'{r:.2f}' for r in ratios)}); "
          f"target >= 1.7x on 2 cores: {'met' if ratio >= 1.7 else 'NOT met'}")
    # the GIL during a run, a check no load hides: Python code of the main thread goes on
    # while another thread simulates (with the GIL held it could not run at all)
    finished = threading.Event()
    worker = threading.Thread(target=lambda: (run(1.0), finished.set()))
    loops = 0
    worker.start()
    while not finished.is_set():
        loops += 1
    worker.join()
    print(f"  the main thread ran {loops} Python loop iterations while another thread simulated "
          f"(0 if the engine held the GIL)")
    return ratio


def thread_cpu_of(call):
    began = time.thread_time()
    result = call()
    return time.thread_time() - began, result


def call_overhead(mbd, rounds):
    """The cost a Python call adds to the engine's run, in two parts measured where they are
    not drowned by the run's own variation: (a) outside the engine, the call's thread CPU time
    minus the engine's within the same call; (b) inside, collecting the rows for the result,
    per row from a run of 20,001 rows (with and without collecting, interleaved), times the
    rows of the run. Also printed: the direct difference of two medians (call, engine alone),
    which a loaded machine makes noisy."""
    model = mbd.load(ROOT / "scenes" / "bench" / "a01-pendulum.yaml")
    calls_per_point = rounds * 5

    def engine_alone(tol, output_step):
        arguments = model._arguments(100.0, "augmented", "dopri5", tol, None, output_step, False, False, None, None,
                                     None, None)
        return lambda keep: mbd._mbd.simulate(model._handle, arguments, keep=keep)["stats"]["thread_cpu_s"]

    dense = engine_alone(1e-6, 0.005)
    dense(True)
    kept, bare = [], []
    for _ in range(calls_per_point):
        kept.append(dense(True))
        bare.append(dense(False))
    per_row = max(0.0, (statistics.median(kept) - statistics.median(bare)) / 20001)
    print(f"overhead: a Python call to simulate on the A01 pendulum (t_end 100 s, rows every 0.5 s: 201 rows, "
          f"augmented + dopri5), {calls_per_point} calls per tolerance; CPU time of the calling thread (the "
          f"engine runs in it); collecting a row costs {per_row * 1e9:.0f} ns")
    worst = 0.0
    for tol in (1e-4, 1e-6, 1e-8, 1e-10, 1e-12):
        alone = engine_alone(tol, 0.5)
        call = lambda: model.simulate(100.0, formulation="augmented", integrator="dopri5", tol=tol, output_step=0.5)
        call()  # warm: plugins loaded
        outside, calls, engine = [], [], []
        for _ in range(calls_per_point):
            spent, result = thread_cpu_of(call)
            calls.append(spent)
            outside.append(spent - result.stats.thread_cpu_s)
            engine.append(alone(False))
        run = statistics.median(engine)
        added = statistics.median(outside) + 201 * per_row
        worst = max(worst, added / run)
        direct = statistics.median(calls) - run
        print(f"  tol {tol:g}: engine {run * 1e3:8.3f} ms; added by Python {added * 1e6:6.1f} us = "
              f"{100 * added / run:5.2f} % (direct difference of medians {direct * 1e6:7.1f} us)")
    print(f"  largest overhead {100 * worst:.2f} % of the run; target < 5 %: {'met' if worst < 0.05 else 'NOT met'}")
    # the same fixed cost with warm caches: calls back to back on a run of one step (t_end 1 ms)
    short = lambda: model.simulate(1e-3, formulation="augmented", integrator="dopri5", tol=1e-4, output_step=1e-3)
    short()
    warm = []
    for _ in range(calls_per_point * 8):
        spent, result = thread_cpu_of(short)
        warm.append(spent - result.stats.thread_cpu_s)
    print(f"  outside the engine with warm caches (calls back to back on a 1 ms run): "
          f"{statistics.median(warm) * 1e6:.1f} us; after a run of milliseconds the interpreter's caches are cold "
          f"again (more so on a loaded machine), which the figures above include")
    return worst


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build", default=str(ROOT / "build"), help="the build tree (its python/ folder is imported)")
    parser.add_argument("--rounds", type=int, default=5)
    args = parser.parse_args()
    sys.path.insert(0, os.path.join(args.build, "python"))
    import numpy as np
    import mbd
    print(f"mbd {mbd.__version__} from {os.path.dirname(mbd.__file__)}; {os.cpu_count()} cores; {load_average()}")
    thread_speedup(mbd, args.rounds, np)
    call_overhead(mbd, args.rounds)
    print(load_average())


if __name__ == "__main__":
    main()
