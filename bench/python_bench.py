#!/usr/bin/env python3
"""The Python module's costs (docs/benchmarks.md, "Python"): run it on a quiet machine with

    /usr/bin/python3 bench/python_bench.py [--build BUILD_DIR] [--rounds N]

1. Threads: 8 independent simulations of one Model (chain-50, embedding + dopri5, 8 initial
   speeds) one after another and through a ThreadPoolExecutor of as many threads as the
   process may use cores; the median over interleaved rounds of serial / parallel wall time
   (the two halves of a round are seconds apart, so a shared machine's slow and fast spells
   mostly cancel in the ratio). Target: >= 1.7 on 2 cores. The parallel results are checked
   bit for bit against the serial ones.
2. Overhead: a Python call model.simulate(...) on the A01 pendulum (scenes/bench/a01-pendulum.yaml
   with its bench settings, t_end 100 s, rows every 0.5 s, augmented + dopri5 at each of its
   tolerances) against the engine's own simulate() on the same settings with nothing collected
   (timed in C++ around the call), both as CPU time of the calling thread, which runs the
   engine, so the load of other processes does not count: (median call - median engine) /
   median engine. Target: < 5 %.
The load average (uptime) is printed before and after: on a busy machine the ratio of part 1
reads low.
"""

import argparse
import concurrent.futures
import os
import pathlib
import statistics
import sys
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
    return ratio


def call_overhead(mbd, rounds):
    model = mbd.load(ROOT / "scenes" / "bench" / "a01-pendulum.yaml")
    print(f"overhead: a Python call to simulate on the A01 pendulum (t_end 100 s, rows every 0.5 s, "
          f"augmented + dopri5), {rounds * 5} calls of each kind per tolerance; CPU time of the calling thread "
          f"(the engine runs in it), so other processes' load does not count")
    worst = 0.0
    for tol in (1e-4, 1e-6, 1e-8, 1e-10, 1e-12):
        keywords = dict(formulation="augmented", integrator="dopri5", tol=tol, output_step=0.5)
        arguments = model._arguments(100.0, "augmented", "dopri5", tol, None, 0.5, False, False, None, None,
                                     None, None)
        model.simulate(100.0, **keywords)  # warm: plugins loaded
        calls, engine = [], []
        for _ in range(rounds * 5):
            began = time.thread_time()
            model.simulate(100.0, **keywords)
            calls.append(time.thread_time() - began)
            # the engine's simulate() alone, nothing collected, timed in C++ around the call
            engine.append(mbd._mbd.simulate(model._handle, arguments, keep=False)["stats"]["thread_cpu_s"])
        call, alone = statistics.median(calls), statistics.median(engine)
        share = (call - alone) / alone
        worst = max(worst, share)
        print(f"  tol {tol:g}: engine {alone * 1e3:8.3f} ms, Python call {call * 1e3:8.3f} ms, "
              f"overhead {(call - alone) * 1e6:7.1f} us = {100 * share:5.2f} %")
    print(f"  largest overhead {100 * worst:.2f} % of the run; target < 5 %: {'met' if worst < 0.05 else 'NOT met'}")
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
