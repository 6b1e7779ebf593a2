#!/usr/bin/env bash
# Cases per second of `mbd sweep` (docs/sweep.md, "Efficiency"; docs/benchmarks.md): a
# 10,000-case Latin hypercube of short pendulum swings (t_end 1 s, dopri5 at tol 1e-6, ten
# output rows) on 1 and 2 threads and on 1 and 2 MPI ranks, the efficiency at 2
# (rate(2) / (2 rate(1))), and the master's CPU time per case (printed by mbd sweep).
# Usage: bench/sweep_bench.sh [BUILD_DIR] [CASES]   (not run by ctest)
set -euo pipefail
build="${1:-build}"
cases="${2:-10000}"
mbd="$(cd "$build" && pwd)/bin/mbd"
source_dir="$(cd "$(dirname "$0")/.." && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cat > "$work/study.yaml" <<YAML
scene: $source_dir/scenes/dynamics/pendulum-a01.yaml
analysis: {type: simulate, t_end: 1, integrator: dopri5, tol: 1.0e-6, output_step: 0.1}
parameters:
  - {path: "bodies.bob.position[0]", distribution: uniform, range: [0.5, 1.5]}
  - {path: bodies.bob.mass, distribution: uniform, range: [0.5, 2.0]}
design: {type: latin_hypercube, cases: $cases, seed: 1}
metrics: [{final: bob.x}, {min: bob.y}, {max: pivot.fy}]
YAML
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
echo "# mbd sweep, $cases cases; $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
# rate LABEL LAUNCHER EXTRA_OPTIONS: prints cases/s (stdout) and a line with the overhead (stderr)
rate() {
  local label="$1" launcher="$2" extra="$3"
  rm -f "$work/r.h5" "$work/r.h5.partial"
  local out; out="$($launcher "$mbd" sweep "$work/study.yaml" -o "$work/r.h5" $extra 2>&1)"
  local r; r="$(sed -n 's/.*(\([0-9.e+]*\) cases\/s).*/\1/p' <<<"$out")"
  local o; o="$(sed -n 's/.*master overhead \([0-9.e+]*\) us.*/\1/p' <<<"$out")"
  printf '%-10s %10s cases/s   master %s us CPU per case\n' "$label" "$r" "$o" >&2
  echo "$r"
}
mpi="mpirun --oversubscribe"
t1=$(rate "1 thread" "" "")
t2=$(rate "2 threads" "" "--threads 2")
r1=$(rate "1 rank" "$mpi -np 1" "")
r2=$(rate "2 ranks" "$mpi -np 2" "")
python3 - "$t1" "$t2" "$r1" "$r2" <<'PY'
import sys
t1, t2, r1, r2 = map(float, sys.argv[1:])
print(f"efficiency at 2 threads {t2 / (2 * t1):.0%}, at 2 ranks {r2 / (2 * r1):.0%}")
PY
