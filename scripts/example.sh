#!/usr/bin/env bash
# Build mbd and run its main jobs on example scenes: the static equilibrium of
# the book's four-bar with a spring (Table 3.2 geometry, Ex. 5.5 spring), then
# two seconds of its damped motion, with the run's cost and constraint error.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh >/dev/null
./build/bin/mbd statics scenes/dynamics/four-bar-spring-damper.yaml
echo
./build/bin/mbd simulate scenes/dynamics/four-bar-spring-damper.yaml --integrator dopri5 --tol 1e-8 \
  --t-end 2 --output build/four-bar.csv --reactions --diagnostics
