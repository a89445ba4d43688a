#!/usr/bin/env python3
"""`biota_bench_wind --compare` on 2 ranks at a toy size, with a Poisson sweep: exits 0, prints the
comparison table with a row per preconditioner (its divergence after projection below 1e-10, the
issue's bound) and a sweep row per size and preconditioner. A smoke test of the command and its
options (parsed with CLI11 since session 41), not a speed check.
Usage: run_bench_wind_smoke.py <biota_bench_wind> <mpiexec>"""
import re
import subprocess
import sys

from smoke_report import finish

bench, mpiexec = sys.argv[1], sys.argv[2]
run = subprocess.run([mpiexec, "-n", "2", bench, "--size", "16", "--steps", "1", "--compare",
                      "--sweep", "8,16"], capture_output=True, text=True, timeout=240)
out = run.stdout
failures = []
if run.returncode != 0:
    failures.append(f"exit code {run.returncode}: {run.stderr.strip()[-400:]}")
names = ["GAMG", "BoomerAMG", "PCMG cell-centred", "PFMG", "GMG matrix-free"]
for name in names:
    m = re.search(rf"^{re.escape(name)}\s+([\d.]+)\s+([\d.]+)\s+([\d.]+)\s+([\d.]+)\s+([\d.e+-]+)$", out, re.M)
    if not m:
        failures.append(f"no comparison row for {name}")
    elif not (float(m.group(1)) > 0 and float(m.group(2)) >= 1 and float(m.group(5)) <= 1e-10):
        failures.append(f"row {m.group(0)!r}: s/step, iterations or divergence out of range")
sweep_rows = re.findall(r"^\s+(8|16)\s+\d+\s+[\d.]+\s+[\d.]+\s+[\d.e+-]+$", out, re.M)
if len(sweep_rows) != 2 * len(names):
    failures.append(f"{len(sweep_rows)} sweep rows, expected {2 * len(names)}")
finish(out, failures, f"bench wind smoke: {len(names)} preconditioners, {len(sweep_rows)} sweep rows")
