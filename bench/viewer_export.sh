#!/usr/bin/env bash
# Animation export benchmark (issue 15; docs/benchmarks.md): a 500-body, 10,000-row result of
# scenes/bench/chain-500.yaml exported with `mbd animate` to .glb and .html (wall time of the
# whole command: scene, CSV reading, writing), then the HTML opened in headless Chromium
# (time from navigation until the viewer has drawn its first frame).
# Usage: bench/viewer_export.sh [BUILD_DIR]   (after cmake --build; default build/)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
out=$build/bench-viewer
mkdir -p "$out"
"$build/bin/mbd_bench_make_chain_result" scenes/bench/chain-500.yaml "$out/chain-500.csv" 10000
ls -l "$out/chain-500.csv" | awk '{printf "CSV: %.0f MB\n", $5 / 1e6}'
for ext in glb html; do
  start=$(date +%s.%N)
  "$build/bin/mbd" animate scenes/bench/chain-500.yaml "$out/chain-500.csv" -o "$out/chain-500.$ext" > /dev/null
  end=$(date +%s.%N)
  size=$(stat -c %s "$out/chain-500.$ext")
  awk -v a="$start" -v b="$end" -v s="$size" -v e="$ext" 'BEGIN { printf "export .%s: %.2f s, %.0f MB\n", e, b - a, s / 1e6 }'
done
node bench/viewer_open.mjs "$out/chain-500.html"
