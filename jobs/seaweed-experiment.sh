#!/usr/bin/env bash
# The seaweed paper's experiment: the three growth stages (cycles 1, 3, 5), 100^3, 20 s of flow
# each, two-way coupling, one after the other on 2 MPI ranks. Writes out/seaweed_c<C>/ per stage and
# out/seaweed_clusters.png (cluster metrics of all three); prints the wall time per stage.
# Usage: jobs/seaweed-experiment.sh [ranks] [extra --set options for every stage...]
# Assumes a build in ./build (jobs/build.sh). Before each stage a short probe (`biota bench lbm`,
# ~4 s, not counted in the stage's time) prints the machine's STREAM bandwidth and LBM rate at that
# moment: on shared VMs they move by 30% within minutes (docs/performance.md, session 8), so a
# stage's time means little without them. SEAWEED_PROBE=0 skips the probe.
set -euo pipefail
cd "$(dirname "$0")/.."
source jobs/mpi-env.sh
ranks=${1:-2}
shift || true
mkdir -p out
total=0
summary=()
for c in 1 3 5; do
  dir=out/seaweed_c$c
  probe=""
  if [[ ${SEAWEED_PROBE:-1} != 0 ]]; then
    probe=$(mpirun -np "$ranks" ./build/biota bench lbm --case D3Q15/bgk --steps 60 --rounds 1 --no-peer \
      --no-two-grid 2>/dev/null | awk '/^STREAM/ {bw = $(NF-1)} /^D3Q15/ {m = $(NF-1)}
        END {if (m != "") printf "machine before it: STREAM %s GB/s, D3Q15 fused %s MLUPS", bw, m}')
  fi
  start=$(date +%s.%N)
  mpirun -np "$ranks" ./build/biota run input/seaweed.toml --set growth.cycles=$c \
    --set output.dir=$dir --set checkpoint.dir=$dir/checkpoints "$@" >"$dir.log" 2>&1 ||
    { echo "stage cycle $c failed: see $dir.log"; exit 1; }
  wall=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN{print b - a}')
  total=$(awk -v a="$total" -v b="$wall" 'BEGIN{print a + b}')
  summary+=("cycle $c: $(printf '%.1f' "$wall") s wall (log $dir.log)${probe:+; $probe}")
  echo "${summary[-1]}"
done
/usr/bin/python3 postproc/plot_clusters.py out/seaweed_clusters.png \
  "cycle 1=out/seaweed_c1" "cycle 3=out/seaweed_c3" "cycle 5=out/seaweed_c5"
printf '%s\n' "${summary[@]}"
echo "all three stages: $(printf '%.1f' "$total") s wall on $ranks ranks; plot: out/seaweed_clusters.png"
