#!/usr/bin/env bash
# Configure and build Biota (Release) into ./build. Usage: jobs/build.sh [extra cmake args]
set -euo pipefail
cd "$(dirname "$0")/.."
jobs/install-deps.sh
cmake --preset release "$@"
cmake --build --preset release -j "$(nproc)"
