#!/usr/bin/env bash
# The main job: install, build, run the default deck on 2 MPI ranks. Output: out/<scenario>/.
# Ctrl-C asks the ranks for a checkpoint (SIGUSR1 to mpirun, which forwards it and waits); a second
# Ctrl-C aborts. (Ctrl-C straight to mpirun gives the ranks 1 s before SIGKILL, too short for a
# large checkpoint: docs/getting-started.md.)
set -euo pipefail
cd "$(dirname "$0")/.."
jobs/build.sh
source jobs/mpi-env.sh
DECK=${1:-input/seaweed.toml}
set -m  # mpirun in a process group of its own: the terminal's Ctrl-C reaches this script only
mpirun -np 2 ./build/biota run "$DECK" &
launcher=$!
interrupts=0 trapped=0
on_interrupt() {
  trapped=1
  interrupts=$((interrupts + 1))
  if ((interrupts == 1)); then
    echo "run-default.sh: Ctrl-C: asking the ranks for a checkpoint (Ctrl-C again to abort)" >&2
    kill -USR1 "$launcher" 2>/dev/null || true
  else
    kill -TERM "$launcher" 2>/dev/null || true
  fi
}
trap on_interrupt INT TERM
rc=0
while :; do  # a trap ends `wait` early; then wait again, or collect the status if mpirun is gone
  trapped=0
  wait "$launcher" && rc=0 || rc=$?
  ((trapped)) || break
  kill -0 "$launcher" 2>/dev/null && continue
  wait "$launcher" && rc=0 || rc=$?
  break
done
trap - INT TERM
((rc == 0)) || exit "$rc"
echo "Results: open out/*/*.pvd (VTK) or out/*/*.xmf (HDF5/XDMF) in ParaView; see docs/getting-started.md"
