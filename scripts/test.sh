#!/usr/bin/env bash
# Build mbd and run the whole test suite (the command CI runs).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/timing.sh
timing_start
bash scripts/build.sh
timing_report "test.sh: dependencies and build took"
cd build
timing_start
status=0
ctest --output-on-failure -j2 --timeout 600 || status=$?
timing_report "test.sh: the test suite took"
exit $status
