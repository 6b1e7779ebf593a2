#!/usr/bin/env bash
# Fuzz with libFuzzer (clang) under AddressSanitizer and UndefinedBehaviorSanitizer:
#   bash scripts/fuzz.sh [SECONDS] [TARGET...]
# SECONDS per target (default 600); TARGETs are scene (the scene loader, from every scene
# under 16 KiB in scenes/ and sdk/examples plus fuzz/seeds/, with fuzz/yaml.dict) and
# command_line (the mbd argument parser, from fuzz/seeds-cli/ with fuzz/command_line.dict);
# default both (scripts/fuzz-ci.sh runs both in CI). The build folder is MBD_FUZZ_BUILD
# (default build-fuzz, configured here when it does not exist yet; CI reuses build-sanitize,
# which scripts/test-sanitizers.sh configures with the fuzz targets). The corpus grows in
# BUILD/corpus/TARGET across runs. Exits non-zero on a finding; the input is left in
# BUILD/findings/TARGET/ (reproduce it with BUILD/bin/TARGET_fuzzer FILE).
set -euo pipefail
seconds=${1:-600}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(scene command_line)
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh >/dev/null  # clang and libclang-rt-dev among them
build=${MBD_FUZZ_BUILD:-build-fuzz}
if [ ! -f "$build/CMakeCache.txt" ]; then
  # -O1 and line tables only: the build is most of a short fuzzing run's time, and -O1 is what
  # libFuzzer's documentation suggests for coverage-guided runs
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -gline-tables-only" \
    -DCMAKE_CXX_COMPILER=clang++ \
    -DMBD_SANITIZE=ON -DMBD_FUZZ=ON -DMBD_BUILD_TESTS=OFF -DMBD_BUILD_BENCH=OFF >/dev/null
elif ! grep -q '^MBD_FUZZ:BOOL=ON' "$build/CMakeCache.txt"; then
  echo "fuzz.sh: $build is not configured with -DMBD_FUZZ=ON (clang); use another MBD_FUZZ_BUILD" >&2
  exit 2
fi
cmake --build "$build" -j2 --target scene_loader_fuzzer command_line_fuzzer mbd_plugins >/dev/null

# The targets run at the same time, one process (one core) each: libFuzzer's default is a single
# process, so CI's two targets take 60 s of wall time together instead of 120 (docs/ci.md). Each
# target's output goes to BUILD/fuzz-TARGET.log and is printed when it ends; any finding fails.
pids=() logs=()
for target in "${targets[@]}"; do
  corpus=$build/corpus/$target findings=$build/findings/$target
  mkdir -p "$corpus" "$findings"
  case $target in
    scene)
      binary=$build/bin/scene_loader_fuzzer dict=fuzz/yaml.dict
      find scenes sdk/examples fuzz/seeds -name '*.yaml' -size -16k -exec cp {} "$corpus"/ \; ;;
    command_line)
      binary=$build/bin/command_line_fuzzer dict=fuzz/command_line.dict
      cp fuzz/seeds-cli/* "$corpus"/ ;;
    *) echo "fuzz.sh: unknown target '$target' (scene, command_line)" >&2; exit 2 ;;
  esac
  log=$build/fuzz-$target.log
  echo "== fuzzing $target for $seconds s (output: $log)"
  # -timeout: an input running 30 s is a hang; -max_len: scenes in the corpus are under 16 KiB
  ASAN_OPTIONS=detect_leaks=1 "$binary" "$corpus" -dict="$dict" -max_total_time="$seconds" -timeout=30 \
    -max_len=16384 -artifact_prefix="$findings"/ -print_final_stats=1 >"$log" 2>&1 &
  pids+=($!) logs+=("$log")
done
status=0
for i in "${!pids[@]}"; do
  target_status=0
  wait "${pids[$i]}" || target_status=$?
  echo "== ${targets[$i]}: exit status $target_status"
  cat "${logs[$i]}"
  [ $target_status -eq 0 ] || status=$target_status
done
exit $status
