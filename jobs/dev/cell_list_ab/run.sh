#!/usr/bin/env bash
# In-process A/B of CellList::for_each_pair: this checkout's header against the one of an older
# revision, on the sphere positions of a seaweed checkpoint. Run on an idle machine.
# Usage: jobs/dev/cell_list_ab/run.sh <old git revision> <seaweed checkpoint.h5> [extra g++ flags]
# e.g.   jobs/dev/cell_list_ab/run.sh 7799780 out/seaweed/checkpoints/seaweed_00001200.h5
#        jobs/dev/cell_list_ab/run.sh 7799780 <checkpoint> -march=x86-64-v3   # the AVX2 path
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../../.." && pwd)
rev=$1 checkpoint=$2
shift 2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
git -C "$root" show "$rev:src/particles/cell_list.hpp" |
  sed 's/namespace biota::particles/namespace biota::particles_old/' >"$work/old_cell_list.hpp"
h5=(-I/usr/include/hdf5/openmpi -L/usr/lib/x86_64-linux-gnu/hdf5/openmpi -lhdf5)
mpicxx -O2 "$here/dump_positions.cpp" "${h5[@]}" -o "$work/dump_positions"
g++ -std=c++20 -O3 -march=native "$@" -I"$root/src" -I"$work" "$here/cell_list_ab.cpp" -o "$work/ab"
"$work/dump_positions" "$checkpoint" "$work/positions.bin"
"$work/ab" "$work/positions.bin"
