#!/bin/sh
# The moss scenario through the executable: 8 days straight on 2 ranks, against 4 days on 3 ranks
# (checkpoint every 2 days) and `--restart latest` for 4 more days on 1 rank. The day-by-day CSV
# (live mosses per species and region, seeds, germinated, died, landed, ...) must be identical
# byte for byte; a changed model key must be refused (exit 2, one line naming it).
set -e
biota=$1; mpiexec=$2; src=$3; work=$4
rm -rf "$work"; mkdir -p "$work"; cd "$work"
common="--set moss.light.photons=1500 --set moss.initial=200 --set moss.outside_spore_interval=2"
$mpiexec -n 2 --oversubscribe "$biota" run "$src/input/moss.toml" $common --set run.steps=8 \
  --set output.dir=\"straight\" --set checkpoint.dir=\"straight/ck\" > straight.log
$mpiexec -n 3 --oversubscribe "$biota" run "$src/input/moss.toml" $common --set run.steps=4 \
  --set checkpoint.interval=2 --set output.dir=\"split\" --set checkpoint.dir=\"split/ck\" > a.log
$mpiexec -n 1 "$biota" run "$src/input/moss.toml" $common --set run.steps=8 \
  --set output.dir=\"split\" --set checkpoint.dir=\"split/ck\" --restart latest > b.log
grep -q "restarted from split/ck/moss_00000004.h5 at step 4" b.log
cmp straight/moss_counts.csv split/moss_counts.csv
test "$(wc -l < split/moss_counts.csv)" -eq 10
set +e
$mpiexec -n 1 "$biota" run "$src/input/moss.toml" $common --set run.steps=10 \
  --set moss.weather.temperature=293.15 --set output.dir=\"split\" --set checkpoint.dir=\"split/ck\" \
  --restart latest > c.log 2>&1
rc=$?
set -e
test $rc -eq 2
test "$(grep -c "biota: error: .*moss.weather.temperature = 288.15 in the checkpoint" c.log)" -eq 1
echo OK
