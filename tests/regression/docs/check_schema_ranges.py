#!/usr/bin/env python3
"""Walk the schema of every scenario (`biota reference`): each integer key must have a finite range
[lo, hi] (an unbounded interval overflowed an `int` to 0 and crashed with SIGFPE, issue 8).
Usage: check_schema_ranges.py <biota>"""
import re
import subprocess
import sys

ref = subprocess.run([sys.argv[1], "reference"], capture_output=True, text=True, check=True).stdout
bad, ints = [], 0
for line in ref.splitlines():
    cols = [c.strip() for c in line.split("|")]
    if len(cols) < 7 or cols[2] != "integer":
        continue
    ints += 1
    if not re.fullmatch(r"\[-?\d+, -?\d+\]", cols[4]):
        bad.append(f"{cols[1]}: {cols[4]}")
for b in bad:
    print(f"integer key without a finite range: {b}")
print(f"{ints - len(bad)}/{ints} integer key rows have a finite range")
sys.exit(1 if bad or ints == 0 else 0)
