#!/usr/bin/env python3
"""Every instantiation of the production LBM sweep (`aa_stream_collide`) in the built binary holds
its software prefetches: at least two per population stream (30 for D3Q15, 38 for D3Q19). The
prefetch made the sweep 1.3-1.5x faster (docs/lbm.md), and GCC drops it silently when it sits in a
function that does nothing else, so a refactor could lose it with every test still green. Reads
the disassembly only; times nothing. Exit 77 (skipped) off x86-64 or without objdump.
Usage: check_lbm_prefetch.py <biota>"""
import platform
import re
import shutil
import subprocess
import sys

if platform.machine() not in ("x86_64", "AMD64") or not shutil.which("objdump"):
    print("not x86-64 or no objdump: skipped")
    sys.exit(77)
dis = subprocess.run(["objdump", "-d", "-C", "--no-show-raw-insn", sys.argv[1]],
                     capture_output=True, text=True, check=True).stdout
counts = {}
current = None
for line in dis.splitlines():
    head = re.match(r"^[0-9a-f]+ <(.*)>:$", line)
    if head:
        name = head.group(1)
        current = name if "aa_stream_collide<" in name and "lambda" not in name else None
        if current:
            counts[current] = 0
    elif current and re.search(r"\tprefetch", line):
        counts[current] += 1
failures = []
if len(counts) < 8:
    failures.append(f"only {len(counts)} aa_stream_collide instantiations found")
for name, n in sorted(counts.items()):
    need = 2 * (19 if "D3Q19" in name else 15)
    if n < need:
        failures.append(f"{n} prefetch instructions (< {need}) in {name}")
for f in failures:
    print("FAIL:", f)
print(f"{len(counts)} instantiations, prefetches per instantiation {min(counts.values(), default=0)}"
      f"-{max(counts.values(), default=0)}")
sys.exit(1 if failures else 0)
