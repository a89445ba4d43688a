#!/usr/bin/python3
"""postproc/scaling.py end to end on a tiny problem: tank and flock, timed at 1 rank, counted at 2
and 3. Checks the CSV columns, the efficiency at the base rank, the counted traffic against the
model columns (tank), the boid count as work (flock) and that the PNGs exist.
Usage: run_scaling_smoke.py <biota> <mpiexec> <source dir>; exit 77 without matplotlib."""
import csv
import os
import subprocess
import sys
import tempfile

BIOTA, MPIEXEC, SRC = sys.argv[1:4]
try:
    import matplotlib  # noqa: F401
except ImportError:
    print("SKIPPED: matplotlib not installed")
    sys.exit(77)

fail = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        fail.append(what)


with tempfile.TemporaryDirectory() as tmp:
    p = subprocess.run([sys.executable, os.path.join(SRC, "postproc", "scaling.py"), "--scenarios",
                        "tank,flock", "--ranks", "1", "--count-ranks", "2,3", "--size", "tiny",
                        "--out", tmp, "--mpiexec", MPIEXEC, "--biota", BIOTA, "--note", "ctest"],
                       capture_output=True, text=True, timeout=400)
    print(p.stdout[-3000:], p.stderr[-3000:])
    check(p.returncode == 0, f"scaling.py exit {p.returncode}")
    rows = list(csv.DictReader(open(os.path.join(tmp, "scaling.csv"))))
    cols = ["scenario", "mode", "ranks", "unit", "work", "timed", "wall_per_step_s", "comm_share",
            "rate", "efficiency", "msgs_per_rank_step_avg", "bytes_per_rank_step_avg",
            "model_bytes_per_rank_step", "dims"]
    check(all(c in rows[0] for c in cols), f"CSV columns {list(rows[0])}")
    key = {(r["scenario"], r["mode"], int(r["ranks"])): r for r in rows}
    check(len(rows) == 3 + 3 + 3, f"{len(rows)} rows (tank strong+weak, flock strong at 1, 2, 3)")
    for mode in ("strong", "weak"):
        r1 = key[("tank", mode, 1)]
        check(r1["efficiency"] == "1.000" and float(r1["wall_per_step_s"]) > 0 and "MLUPS" in r1["rate"],
              f"tank {mode} at 1 rank: efficiency {r1['efficiency']}, {r1['rate']}")
        for P in (2, 3):
            r = key[("tank", mode, P)]
            check(r["timed"] == "0" and r["wall_per_step_s"] == "", f"tank {mode} {P}: counted only")
            check(abs(float(r["bytes_per_rank_step_avg"]) - float(r["model_bytes_per_rank_step"])) <= 1,
                  f"tank {mode} {P} ranks ({r['dims']}): counted {r['bytes_per_rank_step_avg']} B = model "
                  f"{r['model_bytes_per_rank_step']} B")
    f1 = key[("flock", "strong", 1)]
    check(int(f1["work"]) == 1001 and "updates/s" in f1["rate"], f"flock work {f1['work']} boids, {f1['rate']}")
    check(float(key[("flock", "strong", 3)]["bytes_per_rank_step_avg"]) > 0, "flock traffic counted at 3 ranks")
    for s in ("tank", "flock"):
        png = os.path.join(tmp, f"scaling_{s}.png")
        check(os.path.exists(png) and os.path.getsize(png) > 10000, f"{png} written")
sys.exit(1 if fail else 0)
