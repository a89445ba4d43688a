#!/usr/bin/python3
"""Halo traffic model of docs/scaling.md, checked against the bytes and messages the code counts.

    python3 postproc/traffic_model.py [--scenarios tank,wind] [--ranks 1,2,3,4,5,6,7,8] [--n 24]
                                      [--steps 10] [--csv docs/scaling/traffic_model.csv]

Runs each scenario at each rank count (oversubscribed is fine: traffic does not depend on the core
count), reads the decomposition and the "comm:" line of the timing table, and prints the counted
messages and bytes per rank and step beside the model:

- LBM (tank): a rank with block a x b x c sends, per neighbour along x, y, z, the faces
  b c, (a + 2) c, (a + 2)(b + 2) cells (later passes carry the earlier ghosts), 5 populations of
  8 B each (D3Q15 and D3Q19), on every other step (the AA pattern's streaming step; the other
  step is local); plus the 3-component velocity halo (24 B per face
  cell) at every refresh of the macroscopic fields (start, and each output step: 3 per run here).
  The check is exact (to the rounding of the printed averages).
- Wind (MAC, ghost width 2): one exchange of one component of one field sends per neighbour
  2 b c, 2 (a + 4) c, 2 (a + 4)(b + 4) cells of 8 B. The counted bytes divided by that unit give the
  component-exchanges per step; the model holds if that number is the same for every
  decomposition (it is a property of the time stepping: substeps x stages x fields).
Exit status 1 if a check fails.
"""
import argparse
import csv
import os
import re
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def block_start(n, parts, i):
    base, rem = divmod(n, parts)
    return i * base + min(i, rem)


def per_rank_faces(cells, dims, periodic, ghost):
    """For each rank: (messages, face cells) of one exchange of a 1-component field."""
    out = []
    for cz in range(dims[2]):
        for cy in range(dims[1]):
            for cx in range(dims[0]):
                c = (cx, cy, cz)
                size = [block_start(cells[a], dims[a], c[a] + 1) - block_start(cells[a], dims[a], c[a])
                        for a in range(3)]
                sides = []
                for a in range(3):
                    if dims[a] == 1:
                        sides.append(0)  # a periodic image on the same rank is not counted
                    elif periodic[a]:
                        sides.append(2)
                    else:
                        sides.append((c[a] > 0) + (c[a] < dims[a] - 1))
                a_, b_, c_ = size
                g = ghost
                face = (sides[0] * g * b_ * c_ + sides[1] * g * (a_ + 2 * g) * c_ +
                        sides[2] * g * (a_ + 2 * g) * (b_ + 2 * g))
                out.append((sum(sides), face))
    return out


def lbm_model(cells, dims, steps, refreshes=3, populations=5):
    """(avg msgs, max msgs, avg bytes, max bytes) per rank and step. AA pattern: the populations
    cross the block faces on every other step only (steps 1, 3, 5, ... of a run from step 0)."""
    ranks = per_rank_faces(cells, dims, (False,) * 3, 1)
    moves = (steps + 1) // 2
    msgs = [m * (moves + refreshes) / steps for m, _ in ranks]
    byts = [f * (populations * 8 * moves + 3 * 8 * refreshes) / steps for _, f in ranks]
    return sum(msgs) / len(msgs), max(msgs), sum(byts) / len(byts), max(byts)


TANK = ["lbm.inlet.radius=0.05", "lbm.inlet.ramp_time=0"]


def run(scn, ranks, n, steps, mpiexec, biota, tmp):
    d = os.path.join(tmp, f"{scn}_{ranks}")
    if scn == "tank":
        deck = os.path.join(ROOT, "input", "tank.toml")
        sets = [f"lbm.nx={n}", f"lbm.ny={n}", f"lbm.nz={n}", f"lbm.inlet.center=[{n * 0.005}, {n * 0.005}]",
                f"lbm.outlet.center=[{n * 0.005}, {n * 0.005}]", f"lbm.outlet.r_min={n * 0.004}"] + TANK
    else:
        deck = os.path.join(ROOT, "input", "wind.toml")
        sets = [f"wind.nx={2 * n}", f"wind.ny={n}", f"wind.nz={n}"]
    sets += [f"run.steps={steps}", f"run.progress_interval={steps}", "output.interval=0",
             f"output.dir={d}", f"checkpoint.dir={d}/ck"]
    cmd = [mpiexec, "-n", str(ranks), biota, "run", deck]
    for s in sets:
        cmd += ["--set", s]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"traffic_model: {' '.join(cmd)} failed:\n{p.stdout[-1500:]}{p.stderr[-1500:]}")
    m = re.search(r"(\d+) ?x ?(\d+) ?x ?(\d+) ranks", p.stdout)
    dims = tuple(int(x) for x in m.groups())
    m = re.search(r"comm: ranks (\d+) messages/rank/step min ([\d.]+) avg ([\d.]+) max ([\d.]+) "
                  r"bytes/rank/step min (\d+) avg (\d+) max (\d+)", p.stdout)
    if m is None:  # 1 rank: no traffic line fields, or all zero
        return dims, (0.0, 0.0, 0.0, 0.0), ((2 * n, n, n) if scn == "wind" else (n, n, n))
    counted = (float(m.group(3)), float(m.group(4)), float(m.group(6)), float(m.group(7)))
    return dims, counted, ((2 * n, n, n) if scn == "wind" else (n, n, n))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scenarios", default="tank,wind")
    ap.add_argument("--ranks", default="1,2,3,4,5,6,7,8")
    ap.add_argument("--n", type=int, default=24)
    ap.add_argument("--steps", type=int, default=10)
    ap.add_argument("--csv", default="")
    ap.add_argument("--mpiexec", default="mpiexec")
    ap.add_argument("--biota", default=os.path.join(ROOT, "build", "biota"))
    a = ap.parse_args()
    rows, bad = [], 0
    with tempfile.TemporaryDirectory() as tmp:
        for scn in a.scenarios.split(","):
            units = []
            for P in [int(x) for x in a.ranks.split(",")]:
                dims, (mavg, mmax, bavg, bmax), cells = run(scn, P, a.n, a.steps, a.mpiexec, a.biota, tmp)
                row = dict(scenario=scn, ranks=P, dims="x".join(map(str, dims)),
                           cells="x".join(map(str, cells)), steps=a.steps, counted_msgs_avg=mavg,
                           counted_msgs_max=mmax, counted_bytes_avg=bavg, counted_bytes_max=bmax)
                if scn == "tank":
                    pm, pmx, pb, pbx = lbm_model(cells, dims, a.steps)
                    # The printed averages are rounded: messages to 2 decimals, bytes to 1 B.
                    ok = (abs(pm - mavg) < 0.006 and abs(pmx - mmax) < 0.006 and abs(pb - bavg) <= 1
                          and abs(pbx - bmax) <= 1)
                    row.update(model_msgs_avg=round(pm, 3), model_msgs_max=round(pmx, 3),
                               model_bytes_avg=round(pb, 1), model_bytes_max=round(pbx, 1),
                               check="ok" if ok else "FAIL")
                else:
                    ranks = per_rank_faces(cells, dims, (False, True, False), 2)
                    unit = sum(f for _, f in ranks) / len(ranks) * 8
                    per = bavg / unit if unit else 0.0
                    row.update(model_bytes_per_component_exchange=round(unit, 1),
                               component_exchanges_per_step=round(per, 3), check="")
                    if unit:
                        units.append(per)
                bad += row["check"] == "FAIL"
                rows.append(row)
                print(" ".join(f"{k}={v}" for k, v in row.items()), flush=True)
            if units:
                spread = (max(units) - min(units)) / max(units)
                ok = spread < 0.01
                bad += not ok
                print(f"{scn}: component-exchanges per step {min(units):.3f}..{max(units):.3f} over "
                      f"{len(units)} decompositions (spread {spread:.2%}): {'ok' if ok else 'FAIL'}")
    if a.csv:
        keys = []
        for r in rows:
            keys += [k for k in r if k not in keys]
        with open(a.csv, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=keys)
            w.writeheader()
            w.writerows(rows)
        print(f"traffic_model: wrote {a.csv}")
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
