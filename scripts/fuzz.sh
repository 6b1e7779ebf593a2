#!/usr/bin/env bash
# Fuzz the scene loader with libFuzzer (clang) under AddressSanitizer and
# UndefinedBehaviorSanitizer for the given number of seconds (default 600),
# starting from every scene in scenes/. Exits non-zero on a finding; the
# crashing input is left in build-fuzz/findings/.
set -euo pipefail
seconds=${1:-600}
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh >/dev/null
command -v clang++ >/dev/null || { apt-get install -y -qq clang libclang-rt-dev >/dev/null; }
cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
  -DMBD_SANITIZE=ON -DMBD_FUZZ=ON -DMBD_BUILD_TESTS=OFF >/dev/null
cmake --build build-fuzz -j2 --target scene_loader_fuzzer mbd_plugins >/dev/null
mkdir -p build-fuzz/corpus build-fuzz/findings
find scenes sdk/examples -name '*.yaml' -exec cp {} build-fuzz/corpus/ \;
ASAN_OPTIONS=detect_leaks=1 ./build-fuzz/bin/scene_loader_fuzzer build-fuzz/corpus \
  -max_total_time="$seconds" -artifact_prefix=build-fuzz/findings/ -print_final_stats=1
