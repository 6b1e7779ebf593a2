#!/usr/bin/env bash
# The whole test suite built with AddressSanitizer and UndefinedBehaviorSanitizer (issue 8),
# in its own folder build-sanitize (clang, -O1, no benchmarks). A sanitizer report fails its
# test: ASan aborts on the first error and UBSan does not recover (-fno-sanitize-recover=all).
# The same build holds the libFuzzer targets (MBD_FUZZ: the code that reads their inputs is
# instrumented for coverage),
# so that CI's bounded fuzzing (scripts/fuzz-ci.sh) reuses it instead of building everything a
# third time. CI runs it after scripts/test.sh. The Python module is left out of this build
# (MBD_PYTHON defaults to OFF with MBD_SANITIZE: an instrumented extension would need the
# sanitizer runtime preloaded into Debian's uninstrumented python3, whose own allocations the
# leak checker then reports); its tests run in scripts/test.sh's build.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/timing.sh
bash scripts/build-sanitize.sh  # nothing left to do when .ci/run built it beforehand
cd build-sanitize
# intercept_tls_get_addr=0: clang 14's LeakSanitizer tracks the dynamic TLS of dlopened libraries
# through __tls_get_addr and, with Debian 12's glibc, records a bogus block that crashes its tracer
# at exit ("Tracer caught signal 11", seen on `mbd statics`); the leak check itself stays on
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:strict_string_checks=1:check_initialization_order=1:intercept_tls_get_addr=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1}
timing_start
status=0
ctest --output-on-failure -j2 --timeout 900 || status=$?
timing_report "test-sanitizers.sh: the test suite took"
exit $status
