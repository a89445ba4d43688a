"""Plots of a flock run (matplotlib; use /usr/bin/python3):

    /usr/bin/python3 postproc/plot_flock.py <output.dir> <out_prefix>

Writes <out_prefix>_avalanches.png: the avalanche size distribution P(s) on logarithmic bins
(log-log) with the least-squares slope over s >= s_min (eq. 3.4 of the paper, slope only), and
<out_prefix>_polarisation.png: the polarisation (order parameter) over time with the number of
fleeing prey. Prints the fitted exponent. Input: flock_avalanches.csv and flock_order.csv.
"""
import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from script_args import arguments, csv_rows, image_prefix, run_file  # noqa: E402


def log_binned(sizes, per_decade=5):
    """Density per logarithmic bin (count / integers covered), at the geometric bin centre."""
    sizes = [s for s in sizes if s >= 1]
    if not sizes:
        return [], []
    edges = [1]
    while edges[-1] <= max(sizes):
        nxt = max(edges[-1] + 1, int(math.ceil(edges[-1] * 10 ** (1 / per_decade))))
        edges.append(nxt)
    xs, ys = [], []
    n = len(sizes)
    for a, b in zip(edges[:-1], edges[1:]):
        c = sum(1 for s in sizes if a <= s < b)
        if c:
            xs.append(math.sqrt(a * (b - 1)))
            ys.append(c / (b - a) / n)
    return xs, ys


def fit_slope(xs, ys):
    lx = [math.log10(x) for x in xs]
    ly = [math.log10(y) for y in ys]
    n = len(lx)
    if n < 3:
        return float("nan"), 0.0
    mx, my = sum(lx) / n, sum(ly) / n
    sxx = sum((a - mx) ** 2 for a in lx)
    sxy = sum((a - mx) * (b - my) for a, b in zip(lx, ly))
    slope = sxy / sxx
    return slope, my - slope * mx


args = arguments(2, 2)
out_dir, prefix = args[0], image_prefix(args[1])
aval = csv_rows(run_file(out_dir, "flock_avalanches.csv", "flock"), ["size"])
order = csv_rows(run_file(out_dir, "flock_order.csv", "flock"), ["time", "polarisation", "fleeing"])
sizes = [int(r["size"]) for r in aval]
xs, ys = log_binned(sizes)
slope, icpt = fit_slope(xs, ys)
tau = -slope
nonzero = sum(1 for s in sizes if s > 0)
print(f"avalanches: {len(sizes)} drives, {nonzero} with s >= 1, fitted tau = {tau:.3f}")

fig, ax = plt.subplots(figsize=(6, 4.5))
if xs:
    ax.loglog(xs, ys, "o", label="P(s), log bins")
    if not math.isnan(slope):
        fx = [min(xs), max(xs)]
        ax.loglog(fx, [10 ** icpt * x ** slope for x in fx], "-",
                  label=f"fit: tau = {tau:.2f} (3D BTW literature ~1.33)")
ax.set_xlabel("avalanche size s (topplings)")
ax.set_ylabel("P(s)")
ax.set_title(f"Sandpile avalanches during the attack ({nonzero} of {len(sizes)} drives toppled)")
ax.legend()
fig.tight_layout()
fig.savefig(f"{prefix}_avalanches.png", dpi=120)

t = [float(r["time"]) for r in order]
phi = [float(r["polarisation"]) for r in order]
flee = [int(r["fleeing"]) for r in order]
fig, ax = plt.subplots(figsize=(7, 4.5))
ax.plot(t, phi, "-", color="C0", label="polarisation")
ax.set_xlabel("time [s]")
ax.set_ylabel("polarisation")
ax.set_ylim(0, 1.02)
ax2 = ax.twinx()
ax2.plot(t, flee, "-", color="C3", alpha=0.6, label="fleeing prey")
ax2.set_ylabel("fleeing prey")
fig.legend(loc="lower left")
fig.tight_layout()
fig.savefig(f"{prefix}_polarisation.png", dpi=120)
print("wrote", f"{prefix}_avalanches.png", f"{prefix}_polarisation.png")
