#!/usr/bin/env bash
# The threading test (tests/test_threads.cpp: one Model, 8 threads, each with its own Data)
# built with ThreadSanitizer in its own folder build-tsan; a reported data race fails it
# (TSAN_OPTIONS halt_on_error). Only that test and the plugins it loads are built. CI runs it
# after the AddressSanitizer suite.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/timing.sh
bash scripts/install-deps.sh
cmake -S . -B build-tsan -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g1" \
  -DMBD_THREAD_SANITIZER=ON -DMBD_BUILD_BENCH=OFF ${MBD_CMAKE_ARGS:-}
timing_start
cmake --build build-tsan -j2 --target test_threads
timing_report "test-threads.sh: the build took"
cd build-tsan
export TSAN_OPTIONS=${TSAN_OPTIONS:-halt_on_error=1:second_deadlock_stack=1}
ctest --output-on-failure --timeout 900 -R '^Threads\.'
