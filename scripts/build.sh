#!/usr/bin/env bash
# Configure and build mbd into ./build (Release). Installs dependencies first.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release ${MBD_CMAKE_ARGS:-}
cmake --build build -j2
