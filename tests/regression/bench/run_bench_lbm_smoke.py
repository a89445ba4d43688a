#!/usr/bin/env python3
"""`biota bench lbm` on 2 ranks at a toy size: exits 0, prints every round and a table row per
case with the columns jobs/seaweed-experiment.sh reads (the fused MLUPS second to last), and the
D3Q15 / D3Q19 ratio lines. A smoke test of the command's output, not a speed check.
Usage: run_bench_lbm_smoke.py <biota> <mpiexec>"""
import re
import subprocess
import sys

from smoke_report import finish

biota, mpiexec = sys.argv[1], sys.argv[2]
cmd = [mpiexec, "-n", "2", biota, "bench", "lbm", "--size", "16", "--steps", "4", "--rounds", "2",
       "--no-peer"]
run = subprocess.run(cmd, capture_output=True, text=True, timeout=240)
out = run.stdout
failures = []
if run.returncode != 0:
    failures.append(f"exit code {run.returncode}: {run.stderr.strip()[-400:]}")
for r in (1, 2):
    if not re.search(rf"^round {r} MLUPS \(single / fused\):(\s+D3Q1[59]/(bgk|trt) [\d.]+ / [\d.]+){{4}}$",
                     out, re.M):
        failures.append(f"no complete 'round {r}' line")
rows = [line.split() for line in out.splitlines() if re.match(r"^D3Q1[59]\s+(bgk|trt)\s+[\d.]", line)]
# The four production cases (12 columns each) and the former two-grid sweep's line.
cases = [f for f in rows if len(f) == 12]
if sorted((f[0], f[1]) for f in cases) != sorted(
        [("D3Q15", "bgk"), ("D3Q15", "trt"), ("D3Q19", "bgk"), ("D3Q19", "trt")]):
    failures.append(f"table rows: {[' '.join(f) for f in rows]}")
for f in cases:
    mlups, lo_hi, fused = float(f[2]), f[3], float(f[-2])
    lo, hi = (float(v) for v in lo_hi.split("-"))
    if not (mlups > 0 and fused > 0 and lo <= mlups <= hi):
        failures.append(f"row {' '.join(f)}: MLUPS {mlups} outside its rounds {lo_hi} or not positive")
for coll in ("bgk", "trt"):
    if not re.search(rf"^D3Q15 / D3Q19 {coll}: [\d.]+ \(median", out, re.M):
        failures.append(f"no D3Q15 / D3Q19 {coll} line")
if "peer: not run (--no-peer)" not in out:
    failures.append("no line saying the peer was not run")
finish(out, failures, f"bench lbm smoke: {len(cases)} cases, 2 rounds")
