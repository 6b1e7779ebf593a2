#!/usr/bin/env bash
# CI's bounded fuzzing (.ci/run, after the sanitizer run): each fuzz target for
# MBD_FUZZ_SECONDS (default 60) seconds, the two at the same time on the machine's two cores,
# from the committed seeds and dictionaries, with the fuzzers that scripts/test-sanitizers.sh
# built in build-sanitize.
set -euo pipefail
cd "$(dirname "$0")/.."
MBD_FUZZ_BUILD=build-sanitize bash scripts/fuzz.sh "${MBD_FUZZ_SECONDS:-60}" scene command_line
