#!/bin/sh
# Tiny flock run on 2 ranks, then the ParaView render and the avalanche/polarisation plots.
# Skips (exit 77) without ParaView/Xvfb or matplotlib.
set -e
biota=$1; src=$2; work=$3
command -v pvpython >/dev/null && command -v Xvfb >/dev/null || { echo "SKIP: pvpython/Xvfb not found"; exit 77; }
/usr/bin/python3 -c "import matplotlib" 2>/dev/null || { echo "SKIP: python3-matplotlib not installed"; exit 77; }
rm -rf "$work"; mkdir -p "$work"; cd "$work"
mpiexec -n 2 --oversubscribe "$biota" run "$src/input/flock.toml" --set flock.sandpile.size=6 \
  --set flock.domain.size=[32.0,32.0,24.0] --set flock.takeoff.origin=[8.0,8.0,1.0] \
  --set flock.takeoff.scale=14.0 --set flock.predator.start=[4.0,4.0,16.0] \
  --set flock.predator.start_time=2.0 --set flock.sandpile.grains_per_frame=5 \
  --set run.end_time=6.0 --set output.interval=40 --set output.dir=out --set checkpoint.dir=out/ckpt
"$src/postproc/headless.sh" pvpython "$src/postproc/render_flock.py" out snapshot.png
/usr/bin/python3 "$src/postproc/plot_flock.py" out plot
test -s snapshot.png && test -s plot_avalanches.png && test -s plot_polarisation.png
echo OK
