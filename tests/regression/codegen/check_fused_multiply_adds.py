#!/usr/bin/env python3
"""Biota's own functions hold no fused multiply-add that the source does not write.

Biota builds with -ffp-contract=off, so a * b + c rounds twice wherever the source says so, and
the bits do not depend on the compiler's choices (the same on native, x86-64-v3 and baseline
builds; a scalar tail loop the same as its vector lanes). GCC 12's SLP vectoriser breaks that for
one shape: an alternating a*b - c, d*e + f (the quaternion product's rows, a complex multiply)
becomes one vfmaddsub / vfmsubadd even with -ffp-contract=off (`-fdump-tree-slp2-details`:
"Found VEC_FMADDSUB pattern"). Whether it fires depends on inlining: an out-of-line
`core::Quat` product took it under -fno-inline, LTO and PGO, and changed the seaweed deck's bits
(docs/decisions.md). So this test fails when the built binary has
- any vfmaddsub / vfmsubadd in a biota function (the source never writes one), or
- any other FMA instruction in a biota function outside the code that calls std::fma or FMA
  intrinsics on purpose: the LBM collision (biota::solvers::lbm) and the flock's rotate_z
  (inlined into biota::models::flock and FlockScenario).
Reads the disassembly only; times nothing. Exit 77 (skipped) off x86-64 or without objdump.
Usage: check_fused_multiply_adds.py <biota>"""
import re
import sys

from disassembly import functions

WRITTEN_FMA = ("biota::solvers::lbm::", "biota::models::flock::", "biota::scenarios::FlockScenario::")
fma = re.compile(r"\t(vfn?m(?:add|sub)(?:sub|add)?\d*[ps][sd])\b")
addsub = re.compile(r"^vfm(?:addsub|subadd)")

found = {}  # function -> the FMA mnemonics that should not be there
total = 0
for function, lines in functions(sys.argv[1]):
    if "biota::" not in function:
        continue
    written = any(p in function for p in WRITTEN_FMA)
    for line in lines:
        m = fma.search(line)
        if not m:
            continue
        total += 1
        if addsub.match(m.group(1)) or not written:
            found.setdefault(function, set()).add(m.group(1))
for function, mnemonics in sorted(found.items()):
    print(f"FAIL: {', '.join(sorted(mnemonics))} in {function[:300]}")
if found:
    print("The compiler fused multiplies and adds that the source keeps apart (-ffp-contract=off): "
          "this build's results differ in round-off from other builds, and a loop's vector lanes "
          "may differ from its scalar tail. See docs/decisions.md, 'fused multiply-adds'.")
print(f"{total} FMA instructions in biota functions; {len(found)} functions with unwritten ones")
sys.exit(1 if found else 0)
