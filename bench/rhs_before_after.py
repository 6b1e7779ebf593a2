#!/usr/bin/env python3
# Per-rhs cost of every formulation in two builds, side by side (docs/benchmarks.md):
#   bench/rhs_before_after.py OLD_BUILD/bin/bench_rhs NEW_BUILD/bin/bench_rhs [SCENE.yaml...]
# Runs the two bench_rhs programs interleaved, MBD_RHS_ROUNDS times each (default 7), on the same
# scene files (default: chain-5, chain-50, car-axis and a05-flyball of scenes/bench) and prints,
# per scene and formulation, the median over the rounds of each program's time and the median
# over the rounds of the ratio old / new within a round: the two runs of a round are seconds
# apart, so a shared machine's slow and fast spells cancel in the ratio.
import collections
import os
import statistics
import subprocess
import sys

if len(sys.argv) < 3:
    sys.exit("usage: rhs_before_after.py OLD_BENCH_RHS NEW_BENCH_RHS [SCENE.yaml...]")
root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
scenes = sys.argv[3:] or [os.path.join(root, "scenes/bench", s + ".yaml")
                          for s in ("chain-5", "chain-50", "car-axis", "a05-flyball")]
env = dict(os.environ)
env.pop("MBD_PLUGIN_PATH", None)  # each build loads its own plugins
times = {"old": collections.defaultdict(list), "new": collections.defaultdict(list)}
sizes, order = {}, []
rounds = int(os.environ.get("MBD_RHS_ROUNDS", "7"))
for _ in range(rounds):
    for tree, program in (("old", sys.argv[1]), ("new", sys.argv[2])):
        out = subprocess.run([program] + scenes, capture_output=True, text=True, env=env, check=True).stdout
        for line in out.splitlines():
            fields = line.split()
            if len(fields) == 4 and fields[0].endswith(".yaml"):
                key = (fields[0][:-5], fields[1])
                times[tree][key].append(float(fields[3]))
                sizes[key[0]] = fields[2]
                if key not in order:
                    order.append(key)
print("| scene | n_v | formulation | before [us] | after [us] | speed-up |")
print("| --- | --- | --- | --- | --- | --- |")
for key in order:
    before, after = statistics.median(times["old"][key]), statistics.median(times["new"][key])
    ratio = statistics.median(o / n for o, n in zip(times["old"][key], times["new"][key]))
    print("| %s | %s | %s | %.2f | %.2f | %.2fx |" % (key[0], sizes[key[0]], key[1], before, after, ratio))
