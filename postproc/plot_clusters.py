"""Plot the entanglement metrics of several seaweed runs over time:

    python3 postproc/plot_clusters.py out.png label1=dir1 label2=dir2 ...

Each dir holds seaweed_clusters.csv (written by the seaweed scenario). Uses matplotlib (Debian:
python3-matplotlib; with a pyenv python, call /usr/bin/python3).
"""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from script_args import arguments, csv_rows, labelled_runs, png_path  # noqa: E402

args = arguments(2)
out = png_path(args[0])
runs = labelled_runs(args[1:], "seaweed_clusters.csv", "seaweed")
fig, ax = plt.subplots(1, 3, figsize=(14, 4))
for label, path in runs:
    rows = csv_rows(path, ["time", "largest_share", "clusters", "contacts"])
    t = [float(r["time"]) for r in rows]
    ax[0].plot(t, [float(r["largest_share"]) for r in rows], label=label)
    ax[1].plot(t, [int(r["clusters"]) for r in rows], label=label)
    ax[2].plot(t, [int(r["contacts"]) for r in rows], label=label)
    mean = sum(float(r["largest_share"]) for r in rows) / max(1, len(rows))
    print(f"{label}: time-averaged largest-cluster share {mean:.3f}")
for a, y in zip(ax, ["largest-cluster share", "number of clusters", "inter-plant contacts"]):
    a.set_xlabel("time [s]")
    a.set_ylabel(y)
    a.legend()
ax[0].set_ylim(0, 1.05)
fig.tight_layout()
fig.savefig(out, dpi=120)
print("wrote", out)
