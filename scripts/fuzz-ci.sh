#!/usr/bin/env bash
# CI's bounded fuzzing (.ci/run, after the sanitizer run): each fuzz target for
# MBD_FUZZ_SECONDS (default 60) seconds, from the committed seeds and dictionaries.
# scripts/fuzz.sh installs clang and libclang-rt-dev when missing.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/fuzz.sh "${MBD_FUZZ_SECONDS:-60}" scene command_line
