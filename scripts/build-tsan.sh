#!/usr/bin/env bash
# Configure and build the ThreadSanitizer tree build-tsan: only the threading test and the
# plugins it loads (issue 12). scripts/test-threads.sh runs it before the test; .ci/run starts it
# early, at the lowest priority, beside the other builds and suites (docs/ci.md).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/timing.sh
bash scripts/install-deps.sh
cmake -S . -B build-tsan -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g1" \
  -DMBD_THREAD_SANITIZER=ON -DMBD_BUILD_BENCH=OFF ${MBD_CMAKE_ARGS:-}
timing_start
cmake --build build-tsan -j2 --target test_threads
timing_report "build-tsan.sh: the build took"
