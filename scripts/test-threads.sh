#!/usr/bin/env bash
# The threading test (tests/test_threads.cpp: one Model, 8 threads, each with its own Data)
# built with ThreadSanitizer in its own folder build-tsan; a reported data race fails it
# (TSAN_OPTIONS halt_on_error). Only that test and the plugins it loads are built. CI runs it
# after the AddressSanitizer suite.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build-tsan.sh  # nothing left to do when .ci/run built it beforehand
cd build-tsan
export TSAN_OPTIONS=${TSAN_OPTIONS:-halt_on_error=1:second_deadlock_stack=1}
ctest --output-on-failure --timeout 900 -R '^Threads\.'
