#!/usr/bin/env bash
# Configure and build the sanitizer tree build-sanitize: clang, -O1 -g1, AddressSanitizer and
# UndefinedBehaviorSanitizer, the libFuzzer targets with it, no benchmarks (issue 8, issue 20).
# scripts/test-sanitizers.sh runs it before its suite; .ci/run starts it early, at the lowest
# priority, so that it compiles on what the Release build and suite leave idle (docs/ci.md).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/timing.sh
bash scripts/install-deps.sh  # clang and libclang-rt-dev among them
cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g1" \
  -DCMAKE_CXX_COMPILER=clang++ -DMBD_SANITIZE=ON -DMBD_FUZZ=ON -DMBD_BUILD_BENCH=OFF ${MBD_CMAKE_ARGS:-}
timing_start
cmake --build build-sanitize -j2
timing_report "build-sanitize.sh: the build took"
