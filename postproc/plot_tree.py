"""Tip displacement against time for several runs (e.g. the tree paper's 5, 7 and 10 m/s):

    python3 postproc/plot_tree.py <out.png> <label>=<output.dir> [<label>=<output.dir> ...]

Reads <output.dir>/trees.csv of each run (the scenario's per-tree series) and plots the tip
displacement of every tree (one line per tree and run, the run's colour).
"""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from script_args import arguments, csv_rows, labelled_runs, png_path  # noqa: E402

args = arguments(2)
png = png_path(args[0])
runs = labelled_runs(args[1:], "trees.csv", "tree")
fig, ax = plt.subplots(figsize=(7, 4.5))
for n, (label, path) in enumerate(runs):
    series = {}
    for row in csv_rows(path, ["tree", "time", "tip_displacement"]):
        series.setdefault(int(row["tree"]), []).append(
            (float(row["time"]), float(row["tip_displacement"])))
    colour = "C%d" % n
    for k, (tree, pts) in enumerate(sorted(series.items())):
        ax.plot([p[0] for p in pts], [p[1] for p in pts], color=colour,
                label=label if k == 0 else None)
ax.set_xlabel("time (s)")
ax.set_ylabel("tip displacement (m)")
ax.set_title("Tree tip displacement in the wind")
ax.legend()
ax.grid(alpha=0.3)
fig.tight_layout()
fig.savefig(png, dpi=120)
print("wrote", png)
