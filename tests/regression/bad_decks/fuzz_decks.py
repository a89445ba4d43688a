#!/usr/bin/env python3
"""Seeded mutation fuzzing of the deck parser and --set values (issue 8): every mutated deck must
give exit 0 (still valid) or exit 2 with exactly one 'biota: error:' line, never a crash, a hang
or an output directory. `biota check` builds the scenario (all derived checks, decomposition,
memory estimate) without running it. Usage: fuzz_decks.py <biota> [cases] [seed]"""
import os
import random
import subprocess
import sys
import tempfile

BIOTA = sys.argv[1]
CASES = int(sys.argv[2]) if len(sys.argv) > 2 else 60
rng = random.Random(int(sys.argv[3]) if len(sys.argv) > 3 else 8)

BASE = {
    "tank": 'scenario = "tank"\n[run]\nsteps = 2\n[output]\ndir = "{out}"\n[checkpoint]\n'
            'dir = "{out}/ckpt"\n[lbm]\nnx = 8\nny = 8\nnz = 8\ntau = 0.6\n[lbm.inlet]\n'
            'face = "z_lo"\ncenter = [0.04, 0.04]\nradius = 0.02\nspeed = 0.01\n',
    "flock": 'scenario = "flock"\n[run]\nsteps = 2\n[output]\ndir = "{out}"\n[checkpoint]\n'
             'dir = "{out}/ckpt"\n[flock]\nstats_interval = 5\n[flock.sandpile]\nsize = 4\n',
}
TOKENS = ["-1", "0", "1", "2.5", "1e308", "-1e308", "nan", "inf", "-inf", "9223372036854775807",
          "4294967296", '"x"', '""', "[]", "[1, 2]", "[5, 5]", "[1e9, 1e9, 1e9]", "true", "{}",
          "'''", "[", "]", "=", "\\u0000", "0x10", "1_000", "100000"]
KEYS = ["run.steps", "lbm.nx", "lbm.tau", "lbm.inlet.center", "lbm.inlet.radius", "seed",
        "flock.stats_interval", "flock.sandpile.size", "flock.predator.start", "output.interval",
        "flock.noise.levels", "lbm.lattice", "flock.domain.dx"]


def mutate(text):
    lines = text.splitlines()
    kind = rng.randrange(6)
    i = rng.randrange(len(lines))
    if kind == 0 and "=" in lines[i]:  # replace a value
        lines[i] = lines[i].split("=")[0] + "= " + rng.choice(TOKENS)
    elif kind == 1:  # delete a line
        del lines[i]
    elif kind == 2:  # duplicate a line (duplicate keys/tables)
        lines.insert(i, lines[i])
    elif kind == 3:  # flip characters
        s = list(lines[i]) or [" "]
        for _ in range(rng.randint(1, 3)):
            s[rng.randrange(len(s))] = chr(rng.randrange(32, 127))
        lines[i] = "".join(s)
    elif kind == 4:  # truncate the deck
        lines = lines[:i]
    return "\n".join(lines) + "\n", []


def mutate_set():
    return ["--set", f"{rng.choice(KEYS)}={rng.choice(TOKENS)}"]


failures = 0
with tempfile.TemporaryDirectory() as tmp:
    for case in range(CASES):
        scen = rng.choice(sorted(BASE))
        out = os.path.join(tmp, f"out{case}")
        text, extra = mutate(BASE[scen].replace("{out}", out))
        if rng.random() < 0.4:
            extra = mutate_set()
        deck = os.path.join(tmp, f"deck{case}.toml")
        with open(deck, "w") as f:
            f.write(text)
        try:
            p = subprocess.run([BIOTA, "check", deck] + extra, capture_output=True, text=True,
                               timeout=30)
        except subprocess.TimeoutExpired:
            print(f"FAIL case {case}: hang (> 30 s) {extra}\n{text}")
            failures += 1
            continue
        errs = [l for l in p.stderr.splitlines() if l.startswith("biota: error:")]
        ok = (p.returncode == 0 and not errs) or (p.returncode == 2 and len(errs) == 1)
        ok = ok and not os.path.exists(out)
        if not ok:
            failures += 1
            print(f"FAIL case {case}: exit {p.returncode} {extra}\n{text}\n{p.stderr[-600:]}")
print(f"{CASES - failures}/{CASES} mutated decks handled (exit 0, or exit 2 with one line)")
sys.exit(1 if failures else 0)
