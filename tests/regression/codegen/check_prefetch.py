#!/usr/bin/env python3
"""The hot loops that gained from a software prefetch still hold it in the built binary:
- every instantiation of the production LBM sweep (`aa_stream_collide`): at least two prefetches
  per population stream (30 for D3Q15, 38 for D3Q19); the sweep is 1.3-1.5x faster with them
  (docs/lbm.md);
- the seaweed joint gather in `SeaweedBodies::block_forces`: at least three (the child columns'
  loop and the parent record's two lines); the particle step is 0.82-0.88x with them
  (docs/performance-seaweed.md, session 24).
GCC drops a prefetch silently when it sits in a function that does nothing else, so a refactor
could lose one with every test still green. Reads the disassembly only; times nothing. Exit 77
(skipped) off x86-64 or without objdump.
Usage: check_prefetch.py <biota>"""
import re
import sys

from disassembly import functions


def is_lbm_sweep(name):
    return "aa_stream_collide<" in name and "lambda" not in name


def is_joint_gather(name):
    return name.startswith("biota::models::plants::SeaweedBodies::block_forces(")


counts = {name: sum(1 for line in lines if re.search(r"\tprefetch", line))
          for name, lines in functions(sys.argv[1]) if is_lbm_sweep(name) or is_joint_gather(name)}
sweeps = {n: c for n, c in counts.items() if is_lbm_sweep(n)}
gathers = {n: c for n, c in counts.items() if is_joint_gather(n)}
failures = []
if len(sweeps) < 8:
    failures.append(f"only {len(sweeps)} aa_stream_collide instantiations found")
for name, n in sorted(sweeps.items()):
    need = 2 * (19 if "D3Q19" in name else 15)
    if n < need:
        failures.append(f"{n} prefetch instructions (< {need}) in {name}")
if len(gathers) != 1:
    failures.append(f"{len(gathers)} SeaweedBodies::block_forces found (expected 1)")
for name, n in gathers.items():
    if n < 3:
        failures.append(f"{n} prefetch instructions (< 3) in {name}")
for f in failures:
    print("FAIL:", f)
print(f"{len(sweeps)} sweep instantiations, prefetches per instantiation "
      f"{min(sweeps.values(), default=0)}-{max(sweeps.values(), default=0)}; "
      f"joint gather {sum(gathers.values())}")
sys.exit(1 if failures else 0)
