#!/bin/sh
# Tiny tree run (two trees, coarse wind, 0.5 s) on 2 ranks at two wind speeds, then the ParaView
# render (tubes, wind slice, streamlines) and the tip-displacement plot.
# Skips (exit 77) without ParaView/Xvfb or matplotlib.
set -e
biota=$1; src=$2; work=$3
command -v pvpython >/dev/null && command -v Xvfb >/dev/null || { echo "SKIP: pvpython/Xvfb not found"; exit 77; }
/usr/bin/python3 -c "import matplotlib" 2>/dev/null || { echo "SKIP: python3-matplotlib not installed"; exit 77; }
rm -rf "$work"; mkdir -p "$work"; cd "$work"
for u in 5 10; do
  mpiexec -n 2 --oversubscribe "$biota" run "$src/input/tree.toml" --set wind.nx=20 --set wind.ny=10 \
    --set wind.nz=10 --set wind.dx=1.0 --set tree.count=2 --set "tree.positions=[6.0,5.0,0.0,10.0,5.5,0.0]" \
    --set tree.species1.derivations=2 --set wind.inflow.speed=$u --set run.end_time=0.5 \
    --set output.interval=15 --set output.dir=out$u --set checkpoint.dir=out$u/ckpt
done
"$src/postproc/headless.sh" pvpython "$src/postproc/render_tree.py" out10 snapshot.png
/usr/bin/python3 "$src/postproc/plot_tree.py" tips.png "5 m/s=out5" "10 m/s=out10"
test -s snapshot.png && test -s tips.png
# Mistakes a user makes with the scripts: one line on stderr and exit 2 each, no image written
# (they used to end in a traceback, or wrote a figure named after the mistyped argument).
expect_error() {  # <text the line must hold> <command...>
  needle=$1; shift; rc=0
  "$@" >stdout.txt 2>stderr.txt || rc=$?
  lines=$(grep -c "error:" stderr.txt || true)
  if [ "$rc" != 2 ] || [ "$lines" != 1 ] || ! grep -q -F "$needle" stderr.txt; then
    echo "FAIL: $* gave exit $rc and:"; cat stderr.txt; exit 1
  fi
}
expect_error "'nowhere' is not a directory" /usr/bin/python3 "$src/postproc/plot_tree.py" t.png a=nowhere
mkdir -p empty
expect_error "empty/trees.csv: no such file" /usr/bin/python3 "$src/postproc/plot_tree.py" t.png a=empty
expect_error "'out10': expected <label>=<output.dir>" /usr/bin/python3 "$src/postproc/plot_tree.py" t.png out10
expect_error "the image path must end in .png" /usr/bin/python3 "$src/postproc/plot_tree.py" t.pdf a=out10
head -1 out10/trees.csv > empty/trees.csv
expect_error "empty/trees.csv: no rows yet" /usr/bin/python3 "$src/postproc/plot_tree.py" t.png a=empty
expect_error "index 99: tree_nodes.pvd has" "$src/postproc/headless.sh" pvpython "$src/postproc/render_tree.py" out10 r.png 99
expect_error "empty/tree_nodes.pvd: no such file" "$src/postproc/headless.sh" pvpython "$src/postproc/render_tree.py" empty r.png
test ! -e t.png && test ! -e t.pdf && test ! -e r.png
echo OK
