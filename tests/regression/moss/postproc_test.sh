#!/bin/sh
# Tiny moss runs on 2 ranks (indirect light on and off, 6 days, 1024 photons), then the ParaView
# render and the count plot. Skips (exit 77) without ParaView/Xvfb or matplotlib.
set -e
biota=$1; src=$2; work=$3
command -v pvpython >/dev/null && command -v Xvfb >/dev/null || { echo "SKIP: pvpython/Xvfb not found"; exit 77; }
/usr/bin/python3 -c "import matplotlib" 2>/dev/null || { echo "SKIP: python3-matplotlib not installed"; exit 77; }
rm -rf "$work"; mkdir -p "$work"; cd "$work"
for run in on off; do
  indirect=true; [ "$run" = off ] && indirect=false
  mpiexec -n 2 --oversubscribe "$biota" run "$src/input/moss.toml" --set run.steps=6 \
    --set moss.light.photons=1024 --set moss.initial=64 --set moss.light.indirect=$indirect \
    --set output.interval=3 --set output.dir=\"$run\" --set checkpoint.dir=\"$run/ckpt\"
done
"$src/postproc/headless.sh" pvpython "$src/postproc/render_moss.py" on snapshot.png
/usr/bin/python3 "$src/postproc/plot_moss.py" plot indirect=on direct=off
test -s snapshot.png && test -s plot_counts.png
echo OK
