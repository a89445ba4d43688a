#!/usr/bin/env bash
# The main job: install, build, run the default deck on 2 MPI ranks. Output: out/<scenario>/.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs/build.sh
source jobs/mpi-env.sh
DECK=${1:-input/seaweed.toml}
mpirun -np 2 ./build/biota run "$DECK"
echo "Results: open out/*/*.pvd (VTK) or out/*/*.xmf (HDF5/XDMF) in ParaView; see docs/getting-started.md"
