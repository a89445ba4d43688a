#!/usr/bin/env bash
# The seaweed's weak-scaling figure (issue 11): the particle cost per sphere and physics step of
# input/seaweed.toml at cycle 3 in tanks k = 1, 3, 10 (and on request 30) times the volume, scaled
# by s = k^(1/3) in every length, with k times the plants at the same density
# (docs/performance-seaweed.md, session 32).
#
# Each size first grows to t = 1.5 s once (the checkpoint is kept in out/weak_scaling/<k>x and
# reused by later calls). Then the window t = 1.5 to 2.0 s (30 physics steps, a settled state) is
# restarted from it (the window's steps read from its log), in rounds that interleave the sizes; each run waits until the 1-minute load is
# below 1.0. Printed per run and as medians: the slowest rank's particles timer per sphere and
# physics step, and its ratio to the first size's median.
#
# Usage: jobs/seaweed-weak-scaling.sh [ranks] [rounds] [sizes]
#   defaults: 2 ranks, 3 rounds, sizes "1 3 10" (about 10 minutes on 2 cores, 2.6 GB at 10x);
#   "1 3 10 30" adds the 30x case (271 165 spheres, 3.8 GB per rank on 2 ranks, 6 minutes to grow).
# Assumes a build in ./build (jobs/build.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
source jobs/mpi-env.sh
ranks=${1:-2}
rounds=${2:-3}
sizes=${3:-1 3 10}
base=out/weak_scaling
mkdir -p "$base"

# Sets `scaled` to the deck's lengths times s for the k-times case: cells per axis, plants,
# placement box, environment radius, inlet and outlet. The 10x row is the case of earlier sessions'
# figures.
scaled_args() {
  local n plants lo hi env c r rmin
  case $1 in
  1) n=100 plants=50 lo=0.2,0.2,0.25 hi=0.8,0.8,0.75 env=0.3 c=0.5,0.5 r=0.08 rmin=0.35 ;;
  3) n=144 plants=150 lo=0.288,0.288,0.36 hi=1.152,1.152,1.08 env=0.432 c=0.72,0.72 r=0.1152 rmin=0.504 ;;
  10) n=215 plants=500 lo=0.43,0.43,0.54 hi=1.72,1.72,1.61 env=0.645 c=1.075,1.075 r=0.172 rmin=0.75 ;;
  30) n=311 plants=1500 lo=0.622,0.622,0.7775 hi=2.488,2.488,2.333 env=0.933 c=1.555,1.555 r=0.2488 rmin=1.088 ;;
  *) echo "seaweed-weak-scaling: size $1 is not one of 1, 3, 10, 30" >&2; exit 2 ;;
  esac
  scaled=(--set "lbm.nx=$n" --set "lbm.ny=$n" --set "lbm.nz=$n" --set "seaweed.plants=$plants"
    --set "seaweed.placement.lo=[$lo]" --set "seaweed.placement.hi=[$hi]"
    --set "growth.env_radius=$env" --set "lbm.inlet.center=[$c]" --set "lbm.inlet.radius=$r"
    --set "lbm.outlet.center=[$c]" --set "lbm.outlet.r_min=$rmin")
}

source jobs/wait-idle.sh

# Refuse nonsense before any run.
for v in ranks rounds; do
  [[ ${!v} =~ ^[1-9][0-9]*$ ]] ||
    { echo "seaweed-weak-scaling: $v = '${!v}' is not a positive integer" >&2; exit 2; }
done
[ -n "${sizes// /}" ] || { echo "seaweed-weak-scaling: sizes is empty; allowed: 1, 3, 10, 30" >&2; exit 2; }
for k in $sizes; do scaled_args "$k"; done
common=(input/seaweed.toml --set growth.cycles=3 --set output.interval=1000000)
# The grown case's checkpoint: the newest in its directory (the run's final one, at t = 1.5 s).
grown() {
  local f newest=""
  for f in "$base/${1}x/checkpoints"/seaweed_*.h5; do [ -e "$f" ] && newest=$f; done
  echo "$newest"
}
for k in $sizes; do
  [ -n "$(grown "$k")" ] && continue
  echo "growing the ${k}x case to t = 1.5 s (log $base/${k}x.log)"
  scaled_args "$k"
  mpirun -np "$ranks" ./build/biota run "${common[@]}" --set run.end_time=1.5 \
    --set "output.dir=$base/${k}x" "${scaled[@]}" >"$base/${k}x.log" 2>&1 ||
    { echo "growing the ${k}x case failed: see $base/${k}x.log" >&2; exit 1; }
done

results=$base/results.txt
: >"$results"
for round in $(seq "$rounds"); do
  for k in $sizes; do
    wait_idle >/dev/null
    load=$(cut -d' ' -f1 /proc/loadavg)
    log=$base/${k}x_window.log
    scaled_args "$k"
    mpirun -np "$ranks" ./build/biota run "${common[@]}" --set run.end_time=2.0 \
      --restart "$(grown "$k")" --set "output.dir=$base/${k}x_window" \
      --set "checkpoint.dir=$base/${k}x_window/checkpoints" "${scaled[@]}" >"$log" 2>&1 ||
      { echo "the ${k}x window failed: see $log" >&2; exit 1; }
    rm -rf "$base/${k}x_window/checkpoints"
    spheres=$(grep -o '[0-9]* spheres' "$log" | head -1 | cut -d' ' -f1)
    slowest=$(awk '/^particles /{print $4}' "$log")
    # Physics steps of the window: from the restart's step to the last progress line's total.
    step0=$(sed -n 's/^restarted from .* at step \([0-9]*\),.*/\1/p' "$log")
    last=$(sed -n 's/^step *[0-9]*\/\([0-9]*\) .*/\1/p' "$log" | tail -1)
    us=$(awk -v t="$slowest" -v n="$spheres" -v s="$((last - step0))" \
      'BEGIN{printf "%.3f", t / (n * s) * 1e6}')
    echo "$k $us" >>"$results"
    echo "round $round, ${k}x: $spheres spheres, particles $slowest s (slowest rank), $us us per sphere and physics step (load $load at the start)"
  done
done

echo "medians over $rounds round(s), $ranks ranks:"
first=""
for k in $sizes; do
  median=$(awk -v k="$k" '$1 == k {print $2}' "$results" | sort -g |
    awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}')
  first=${first:-$median}
  awk -v k="$k" -v m="$median" -v f="$first" \
    'BEGIN{printf "  %3sx: %.3f us per sphere and physics step, %.2fx the %s\n", k, m, m / f, "first size"}'
done
