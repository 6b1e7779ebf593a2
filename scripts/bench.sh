#!/usr/bin/env bash
# Regenerates the work-precision benchmark (docs/benchmarks.md, section between the
# work-precision markers) and its plots and tables in docs/benchmarks/:
#   1. builds mbd, its plugins, the rhs benchmarks and the peers (bench/peers/: Simbody and MuJoCo,
#      installed by scripts/install-deps.sh) into $MBD_BENCH_BUILD (default: build); a missing
#      peer stops the script before anything is written, so the committed peer columns of
#      docs/benchmarks.md are never replaced by empty ones;
#   2. `mbd bench scenes/bench/*.yaml` with the peers -> work-precision.csv / .json;
#   3. per-step cost against body count for every formulation (scripts/bench_scaling.py) and the
#      rhs benchmarks bench_augmented / bench_embedding (reduced sizes);
#   4. scripts/bench_report.py: one work-precision diagram per scene (PNG, SVG), the scaling plot,
#      and the tables in docs/benchmarks.md: each engine's CPU time at error 1e-6 and 1e-9, read
#      by log-log interpolation on its own work-precision curves (scripts/work_precision.py).
# Budget: the last run (docs/benchmarks.md) took 281 s on the coarse grids of then (steps of 100);
# the grids of scenes/bench now step by sqrt(10) in tolerance and 1.5 in step, about three times
# the points, so expect about three times that.
# Options (environment): MBD_BENCH_REPEAT (3), MBD_BENCH_SCENES (all of scenes/bench), MBD_BENCH_SKIP_BUILD=1.
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
BUILD=${MBD_BENCH_BUILD:-build}
OUT=docs/benchmarks
mkdir -p "$OUT"
if [ "${MBD_BENCH_SKIP_BUILD:-0}" != 1 ]; then
  bash scripts/install-deps.sh
  cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=Release >/dev/null
  targets=(mbd mbd_plugins bench_augmented bench_embedding)
  help=$(cmake --build "$BUILD" --target help)  # the peers are targets only when their library was found
  for peer in mbd_peer_simbody mbd_peer_mujoco; do
    if grep -q "$peer" <<<"$help"; then targets+=("$peer"); fi
  done
  cmake --build "$BUILD" -j2 --target "${targets[@]}"
fi
MBD="$BUILD/bin/mbd"
for peer in simbody mujoco; do
  if [ ! -x "$BUILD/bin/peers/mbd_peer_$peer" ]; then
    echo "bench.sh: error: the $peer peer ($BUILD/bin/peers/mbd_peer_$peer) is not built, so the benchmark" \
      "would overwrite the committed $peer columns of docs/benchmarks.md with nothing; nothing was written." \
      "Install it (bash scripts/install-deps.sh: libsimbody-dev, libmujoco-dev), re-run cmake on $BUILD" \
      "and build again, or run \`mbd bench\` by hand for a private comparison." >&2
    exit 1
  fi
done
# Debian's python3-matplotlib belongs to /usr/bin/python3; another python3 first on PATH may lack it.
PY=${PYTHON:-python3}
if ! "$PY" -c "import matplotlib" 2>/dev/null && [ -x /usr/bin/python3 ]; then PY=/usr/bin/python3; fi
scenes=${MBD_BENCH_SCENES:-$(ls scenes/bench/*.yaml)}
# shellcheck disable=SC2086
"$MBD" bench $scenes --repeat "${MBD_BENCH_REPEAT:-3}" --peers "$BUILD/bin/peers" \
  --csv "$OUT/work-precision.csv" --json "$OUT/work-precision.json"
"$PY" scripts/bench_scaling.py "$MBD" "$OUT/scaling.csv"
{
  "$BUILD/bin/bench_augmented" 3000 300 || echo "bench_augmented failed"
  "$BUILD/bin/bench_embedding" 3000 100 || echo "bench_embedding failed"
} > "$OUT/rhs-scaling.txt" 2>&1
end=$(date +%s)
"$PY" scripts/bench_report.py "$OUT" docs/benchmarks.md --scaling "$OUT/scaling.csv" \
  --rhs "$OUT/rhs-scaling.txt" --wall $((end - start))
echo "bench.sh: done in $((end - start)) s (plots and tables in $OUT, docs/benchmarks.md)"
