#!/usr/bin/env bash
# Build mbd and run the whole test suite (the command CI runs).
set -euo pipefail
cd "$(dirname "$0")/.."
start=$SECONDS
bash scripts/build.sh
echo "test.sh: dependencies and build took $((SECONDS - start)) s"
cd build
start=$SECONDS
status=0
ctest --output-on-failure -j2 --timeout 600 || status=$?
echo "test.sh: the test suite took $((SECONDS - start)) s"
exit $status
