#!/usr/bin/env bash
# Install, build and run the whole test suite (unit, MPI at 1-3 ranks, validation, regression).
set -euo pipefail
cd "$(dirname "$0")/.."
jobs/build.sh
source jobs/mpi-env.sh
ctest --preset release
