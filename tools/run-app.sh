#!/usr/bin/env bash
# Installs the dependencies, builds Marbles and starts the application (optional scene file argument).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo
cmake --build build -j "${MARBLES_JOBS:-2}" --target marbles marbles-cli
exec ./build/app/marbles "$@"
