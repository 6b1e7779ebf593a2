#!/usr/bin/env bash
# Build mbd and run the main job on an example scene: assemble the four-bar of
# book Table 3.2, report its mobility, and drive it through a quarter turn.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh >/dev/null
./build/bin/mbd check scenes/four-bar.yaml
./build/bin/mbd kinematics scenes/four-bar.yaml --t-end 0.0314 --step 0.00314
