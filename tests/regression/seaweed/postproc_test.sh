#!/bin/sh
# Tiny seaweed run, then the ParaView render and the cluster plot. Skips (exit 77) without
# ParaView/Xvfb or matplotlib.
set -e
biota=$1; src=$2; work=$3
command -v pvpython >/dev/null && command -v Xvfb >/dev/null || { echo "SKIP: pvpython/Xvfb not found"; exit 77; }
/usr/bin/python3 -c "import matplotlib" 2>/dev/null || { echo "SKIP: python3-matplotlib not installed"; exit 77; }
rm -rf "$work"; mkdir -p "$work"; cd "$work"
for c in 1 2; do
  mpiexec -n 2 --oversubscribe "$biota" run "$src/input/seaweed.toml" --set growth.cycles=$c \
    --set seaweed.plants=4 --set lbm.nx=24 --set lbm.ny=24 --set lbm.nz=24 --set lbm.dx=0.02 \
    --set lbm.dt=0.0033333333333333335 --set lbm.inlet.center=[0.24,0.24] --set lbm.inlet.radius=0.05 \
    --set lbm.outlet.center=[0.24,0.24] --set lbm.outlet.r_min=0.18 \
    --set seaweed.placement.lo=[0.1,0.1,0.1] --set seaweed.placement.hi=[0.38,0.38,0.38] \
    --set growth.env_radius=0.2 --set run.end_time=0.1 --set output.interval=3 \
    --set output.dir=c$c --set checkpoint.dir=c$c/ckpt
done
"$src/postproc/headless.sh" pvpython "$src/postproc/render_seaweed.py" c2 snapshot.png
/usr/bin/python3 "$src/postproc/plot_clusters.py" clusters.png cycle1=c1 cycle2=c2
test -s snapshot.png && test -s clusters.png
echo OK
