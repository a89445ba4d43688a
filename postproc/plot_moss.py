"""Moss counts over the days for the paper's two experiments (matplotlib; /usr/bin/python3):

    /usr/bin/python3 postproc/plot_moss.py <out_prefix> <label>=<output.dir> [<label>=<dir> ...]

Reads <dir>/moss_counts.csv of each run and writes <out_prefix>_counts.png: live mosses over the
days (solid) and those in the region 'back' (under the roof and the back floor, dashed), one
colour per run; e.g. experiment 1 (indirect=out/base direct=out/noind) and experiment 2
(288.15K=out/base 293.15K=out/warm) on one figure. Prints the last row of each run.
"""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from script_args import arguments, csv_rows, image_prefix, labelled_runs  # noqa: E402


COLUMNS = ["day", "live", "back", "open", "roof", "bryum", "hypnum", "polytrichum"]
args = arguments(2)
prefix = image_prefix(args[0])
runs = labelled_runs(args[1:], "moss_counts.csv", "moss")
fig, ax = plt.subplots(figsize=(8, 5))
for k, (label, path) in enumerate(runs):
    rows = csv_rows(path, COLUMNS)
    day = [int(r["day"]) for r in rows]
    colour = f"C{k}"
    ax.plot(day, [int(r["live"]) for r in rows], color=colour, label=f"{label}: all")
    ax.plot(day, [int(r["back"]) for r in rows], color=colour, ls="--",
            label=f"{label}: back (under the roof)")
    last = rows[-1]
    print(f"{label}: day {last['day']} live {last['live']} back {last['back']} open "
          f"{last['open']} roof {last['roof']} (bryum {last['bryum']} hypnum {last['hypnum']} "
          f"polytrichum {last['polytrichum']})")
ax.set_xlabel("day")
ax.set_ylabel("live mosses")
ax.set_title("moss counts over the days")
ax.legend(fontsize=8)
fig.tight_layout()
fig.savefig(f"{prefix}_counts.png", dpi=110)
print("wrote", f"{prefix}_counts.png")
