#!/usr/bin/python3
"""Strong and weak scaling of the tank (LBM), seaweed, wind and flock scenarios in one command.

    python3 postproc/scaling.py [--ranks 1,2] [--count-ranks 3,4,8] [--scenarios tank,seaweed,wind,flock]
                                [--size small|medium] [--out docs/scaling] [--note "under load"]

Timed runs at --ranks (the cores this machine has); runs at --count-ranks are oversubscribed and
only their counted traffic (messages and bytes per rank and step, from the code's own counters in
grid::HaloExchange and particles::ParticleComm, the "comm:" line of the timing table) is used:
traffic does not depend on the core count, times do. Writes <out>/scaling.csv and one PNG per
scenario (speed-up and efficiency with the ideal line, traffic per rank and step).
"""
import argparse
import csv
import os
import re
import subprocess
import sys
import tempfile
import textwrap

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from traffic_model import lbm_model  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# Per scenario: deck, overrides for a problem of base size n (strong: fixed; weak: x grows with P),
# the work unit and how many units one step updates.
TANK = lambda nx, n: ["--set", f"lbm.nx={nx}", "--set", f"lbm.ny={n}", "--set", f"lbm.nz={n}",
                      "--set", f"lbm.inlet.center=[{n * 0.005}, {n * 0.005}]",
                      "--set", "lbm.inlet.radius=0.05", "--set", "lbm.inlet.ramp_time=0",
                      "--set", f"lbm.outlet.center=[{n * 0.005}, {n * 0.005}]",
                      "--set", f"lbm.outlet.r_min={n * 0.004}"]
# Seaweed: 4 small plants in the middle of the tank (placement, environment regions and outlet
# scaled with the box; the deck's own 1 m tank would put them outside a small grid).
SEAWEED = lambda nx, n: TANK(nx, n) + [
    "--set", "growth.cycles=1", "--set", "seaweed.plants=4",
    "--set", f"seaweed.placement.lo=[{nx * 0.003}, {n * 0.003}, {n * 0.002}]",
    "--set", f"seaweed.placement.hi=[{nx * 0.007}, {n * 0.007}, {n * 0.005}]",
    "--set", f"growth.env_radius={n * 0.003}"]
SCENARIOS = {
    "tank": dict(deck="input/tank.toml", unit="cells", mlups=True,
                 args=lambda nx, n: TANK(nx, n), work=lambda nx, n: nx * n * n),
    "seaweed": dict(deck="input/seaweed.toml", unit="cells", mlups=True,
                    args=lambda nx, n: SEAWEED(nx, n), work=lambda nx, n: nx * n * n),
    "wind": dict(deck="input/wind.toml", unit="cells", mlups=True,
                 args=lambda nx, n: ["--set", f"wind.nx={nx}", "--set", f"wind.ny={n}",
                                     "--set", f"wind.nz={n}"],
                 work=lambda nx, n: nx * n * n),
    "flock": dict(deck="input/flock.toml", unit="particles", mlups=False,
                  args=lambda nx, n: [], work=None),
}
SIZES = {"tiny": dict(n=12, steps=6), "small": dict(n=24, steps=60), "medium": dict(n=64, steps=300)}


def run(scn, ranks, nx, n, steps, mpiexec, biota, tmp):
    s = SCENARIOS[scn]
    cmd = [mpiexec, "-n", str(ranks), biota, "run", os.path.join(ROOT, s["deck"])] + s["args"](nx, n) + [
        "--set", f"run.steps={steps}", "--set", f"run.progress_interval={steps}",
        "--set", "output.interval=0", "--set", f"output.dir={tmp}/{scn}_{ranks}_{nx}",
        "--set", f"checkpoint.dir={tmp}/{scn}_{ranks}_{nx}/ck"]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.stderr.write(f"scaling: {' '.join(cmd)} failed ({p.returncode}):\n{p.stdout[-1500:]}{p.stderr[-1500:]}\n")
        return None
    out = p.stdout
    rec = {}
    m = re.search(r"timing breakdown \((\d+) steps\)", out)
    rec["steps"] = int(m.group(1))
    rec["wall"] = float(re.search(r"total wall\s+([\d.]+)", out).group(1))
    comm = 0.0
    for line in out.splitlines():
        f = line.split()
        if len(f) >= 5 and re.search(r"halo|comm|particles$|ghost", f[0] + " " + f[1]) and "%" in f[-1]:
            comm += float(f[-1].rstrip("%"))
    rec["comm_share"] = comm / 100.0
    m = re.search(r"comm: ranks (\d+) messages/rank/step min ([\d.]+) avg ([\d.]+) max ([\d.]+) "
                  r"bytes/rank/step min (\d+) avg (\d+) max (\d+)", out)
    rec["msgs_avg"], rec["msgs_max"] = float(m.group(3)), float(m.group(4))
    rec["bytes_avg"], rec["bytes_max"] = float(m.group(6)), float(m.group(7))
    m = re.findall(r"MLUPS\s+([\d.]+)", out)
    rec["mlups_reported"] = float(m[-1]) if m else None
    m = re.search(r"(\d+) prey, (\d+) predators", out)
    rec["particles"] = int(m.group(1)) + int(m.group(2)) if m else None
    m = re.search(r"(\d+) LBM steps per physics step", out)  # seaweed: cell updates per step
    rec["substeps"] = int(m.group(1)) if m else 1
    m = re.search(r"(\d+) ?x ?(\d+) ?x ?(\d+) ranks", out)
    rec["dims"] = tuple(int(x) for x in m.groups()) if m else None
    # End-of-run checkpoint and output are not steps: take them out of the time per step.
    io = sum(float(x) for x in re.findall(r"^(?:output|checkpoint)\s+\d+ writes, ([\d.]+) s", out, re.M))
    rec["wall_per_step"] = max(rec["wall"] - io, 1e-12) / max(rec["steps"], 1)
    return rec


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--ranks", default="1,2")
    ap.add_argument("--count-ranks", default="3,4,8")
    ap.add_argument("--scenarios", default="tank,seaweed,wind,flock")
    ap.add_argument("--size", default="small", choices=SIZES)
    ap.add_argument("--out", default=os.path.join(ROOT, "docs", "scaling"))
    ap.add_argument("--note", default="")
    ap.add_argument("--mpiexec", default="mpiexec")
    ap.add_argument("--biota", default=os.path.join(ROOT, "build", "biota"))
    ap.add_argument("--plot-only", action="store_true", help="re-plot <out>/scaling.csv")
    a = ap.parse_args()
    if a.plot_only:
        with open(os.path.join(a.out, "scaling.csv")) as f:
            rows = [dict(r, ranks=int(r["ranks"]), timed=int(r["timed"])) for r in csv.DictReader(f)]
        plot(rows, a.out, sorted({r["ranks"] for r in rows if r["timed"]}),
             sorted({r["ranks"] for r in rows if not r["timed"]}), rows[0]["note"], rows[0]["uptime"])
        return
    timed = [int(x) for x in a.ranks.split(",") if x]
    counted = [int(x) for x in a.count_ranks.split(",") if x]
    size = SIZES[a.size]
    os.makedirs(a.out, exist_ok=True)
    uptime = subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for scn in a.scenarios.split(","):
            s = SCENARIOS[scn]
            for mode in ("strong", "weak"):
                base = None
                for P in timed + counted:
                    n = size["n"]
                    nx = n if mode == "strong" else n * P
                    if s["work"] is None and mode == "weak":
                        continue  # flock: the boid count is fixed by the sandpile (L^3)
                    steps = size["steps"] if P in timed else max(5, size["steps"] // 6)
                    r = run(scn, P, nx, n, steps, a.mpiexec, a.biota, tmp)
                    if r is None:
                        continue
                    # Work per step: cell updates (seaweed: LBM substeps per physics step) or boids.
                    work = s["work"](nx, n) * r["substeps"] if s["work"] else (r["particles"] or 0)
                    is_timed = P in timed
                    rate = work / r["wall_per_step"]
                    if base is None and is_timed:
                        base = r["wall_per_step"], work
                    eff = ""
                    if is_timed and base:
                        eff = (base[0] / (P * r["wall_per_step"]) if mode == "strong"
                               else base[0] * work / (base[1] * r["wall_per_step"]))
                    model_b = model_m = ""
                    if scn == "tank" and r["dims"]:
                        mm, _, mb, _ = lbm_model((nx, n, n), r["dims"], r["steps"])
                        model_m, model_b = round(mm, 3), round(mb, 1)
                    rows.append(dict(scenario=scn, mode=mode, ranks=P, unit=s["unit"], work=work,
                                     steps=r["steps"], timed=int(is_timed),
                                     wall_per_step_s=f"{r['wall_per_step']:.6g}" if is_timed else "",
                                     comm_share=f"{r['comm_share']:.3f}" if is_timed else "",
                                     rate=(f"{rate / 1e6:.4g} MLUPS" if s["mlups"] else f"{rate:.4g} updates/s") if is_timed else "",
                                     efficiency=f"{eff:.3f}" if eff != "" else "",
                                     msgs_per_rank_step_avg=r["msgs_avg"], msgs_per_rank_step_max=r["msgs_max"],
                                     bytes_per_rank_step_avg=r["bytes_avg"], bytes_per_rank_step_max=r["bytes_max"],
                                     model_msgs_per_rank_step=model_m, model_bytes_per_rank_step=model_b,
                                     dims="x".join(map(str, r["dims"])) if r["dims"] else "",
                                     note=a.note, uptime=uptime))
                    print(f"{scn:8} {mode:6} P={P:2} work={work:>9} "
                          f"{'t/step=' + format(r['wall_per_step'], '.4g') + ' s' if is_timed else '(counted only)':24} "
                          f"bytes/rank/step={r['bytes_avg']:.0f} msgs={r['msgs_avg']:.2f}", flush=True)
    path = os.path.join(a.out, "scaling.csv")
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    print(f"scaling: wrote {path}")
    plot(rows, a.out, timed, counted, a.note, uptime)


def plot(rows, out, timed, counted, note, uptime):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    num = lambda v: float(v) if v not in ("", None) else None
    for scn in sorted({r["scenario"] for r in rows}):
        fig, ax = plt.subplots(1, 4, figsize=(18, 4.4))
        for mode, mk in (("strong", "o-"), ("weak", "s--")):
            rs = [r for r in rows if r["scenario"] == scn and r["mode"] == mode]
            t = [r for r in rs if int(r["timed"]) and r["efficiency"] not in ("", None)]
            if t:
                P = [r["ranks"] for r in t]
                eff = [float(r["efficiency"]) for r in t]
                # strong: speed-up T1/TP = P E; weak: scaled speed-up P E (work grows with P).
                ax[0].plot(P, [e * p for e, p in zip(eff, P)], mk, label=f"{mode} (measured)")
                ax[1].plot(P, eff, mk, label=f"{mode} (measured)")
            if rs:
                P = [r["ranks"] for r in rs]
                ax[2].plot(P, [num(r["bytes_per_rank_step_avg"]) for r in rs], mk,
                           label=f"{mode}: counted (avg over ranks)")
                ax[3].plot(P, [num(r["msgs_per_rank_step_avg"]) for r in rs], mk,
                           label=f"{mode}: counted (avg over ranks)")
                mb = [(r["ranks"], num(r.get("model_bytes_per_rank_step"))) for r in rs]
                mb = [(p, v) for p, v in mb if v is not None]
                if mb:
                    ax[2].plot(*zip(*mb), "kx", ms=9, label=f"{mode}: model (docs/scaling.md)")
                mm = [(r["ranks"], num(r.get("model_msgs_per_rank_step"))) for r in rs]
                mm = [(p, v) for p, v in mm if v is not None]
                if mm:
                    ax[3].plot(*zip(*mm), "kx", ms=9, label=f"{mode}: model")
        allP = sorted(set(timed + counted))
        ax[0].plot(allP, allP, "k:", label="ideal")
        ax[1].plot(allP, [1] * len(allP), "k:", label="ideal")
        ax[0].set(title=f"{scn}: speed-up", xlabel="ranks", ylabel="speed-up (weak: scaled)")
        ax[1].set(title="efficiency", xlabel="ranks", ylabel="efficiency", ylim=(0, 1.2))
        ax[2].set(title="bytes sent per rank and step", xlabel="ranks", ylabel="bytes")
        ax[3].set(title="messages sent per rank and step", xlabel="ranks", ylabel="messages")
        if counted:
            for x in ax[:2]:
                x.axvspan(max(timed or [0]) + 0.5, max(allP) + 0.5, color="0.9", zorder=0)
                x.text(max(timed or [0]) + 0.7, 0.05, f"no times beyond {max(timed or [0])} ranks\n"
                       "(oversubscribed: counted traffic only, right)",
                       fontsize=7, transform=x.get_xaxis_transform())
        for x in ax:
            x.legend(fontsize=7)
            x.grid(alpha=0.3)
        title = (f"Times measured at {timed} ranks only (one core per rank on this machine); at "
                 f"{counted} ranks the runs were oversubscribed and only the bytes and messages the "
                 f"code counts itself are shown (they do not depend on the core count). {note}")
        fig.suptitle("\n".join(textwrap.wrap(title, 170) + [uptime]), fontsize=8)
        fig.tight_layout()
        fig.savefig(os.path.join(out, f"scaling_{scn}.png"), dpi=90)
        plt.close(fig)
        print(f"scaling: wrote {os.path.join(out, f'scaling_{scn}.png')}")


if __name__ == "__main__":
    main()
