#!/usr/bin/env python3
"""`biota lsystem` as a user runs it: the tree paper's Fig. 1 summary (73 modules, 25 F, height 7),
the --vtk polyline file, and a bad grammar: one line `file:line:col: ...` on stderr, exit 2.
Usage: run_lsystem_cli.py <biota> <source dir>"""
import os
import subprocess
import sys
import tempfile

BIOTA, SRC = sys.argv[1:3]
failures = []


def expect(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)


with tempfile.TemporaryDirectory() as tmp:
    fig1 = os.path.join(SRC, "input", "lsystems", "paper_fig1.lsys")
    p = subprocess.run([BIOTA, "lsystem", fig1, "--vtk", f"{tmp}/fig1.vtp"], capture_output=True,
                       text=True)
    expect(p.returncode == 0, f"biota lsystem exits 0 ({p.stderr})")
    expect("modules: 73" in p.stdout and "F=25" in p.stdout and "segments: 25" in p.stdout,
           "paper Fig. 1: 73 modules, 25 F, 25 segments")
    expect("bracket pairs: 18" in p.stdout and "height: 7.000000" in p.stdout, "18 pairs, height 7")
    with open(f"{tmp}/fig1.vtp") as f:
        vtp = f.read()
    expect('NumberOfLines="25"' in vtp and 'Name="radius"' in vtp, ".vtp: 25 lines with radius")
    p = subprocess.run([BIOTA, "lsystem", fig1, "--derivations", "3"], capture_output=True, text=True)
    expect("F=125" in p.stdout, "--derivations 3: 125 F")
    for lsys in sorted(os.listdir(os.path.join(SRC, "input", "lsystems"))):
        p = subprocess.run([BIOTA, "lsystem", os.path.join(SRC, "input", "lsystems", lsys)],
                           capture_output=True, text=True)
        expect(p.returncode == 0, f"input/lsystems/{lsys} derives ({p.stderr.strip()})")
    bad = f"{tmp}/bad.lsys"
    with open(bad, "w") as f:
        f.write("axiom: F\nangle: 20\nF -> F[+F]F[-F\n")
    p = subprocess.run([BIOTA, "lsystem", bad], capture_output=True, text=True)
    err = p.stderr.strip().splitlines()
    expect(p.returncode == 2, f"bad grammar exits 2 (got {p.returncode})")
    expect(len(err) == 1 and f"{bad}:3:12: unbalanced brackets" in err[0], f"one line: {err}")
    p = subprocess.run([BIOTA, "lsystem", fig1, "--derivations", "9", "--max-modules", "100000"],
                       capture_output=True, text=True)
    expect(p.returncode == 2 and "derivation 7 of 9 exceeds the module cap of 100000 (--max-modules); "
           "allowed: at most 6 derivations" in p.stderr, f"module cap: exit 2, names the options ({p.stderr})")
    # Session 41: a .vtp into a missing folder exited 0 behind VTK's own colour log, a .txt was
    # written as XML, --seed -1 wrapped to 2^64 - 1, a directory read as an empty grammar.
    for args, needle in (([fig1, "--vtk", f"{tmp}/no/such/fig1.vtp"], f"the folder {tmp}/no/such does not exist"),
                         ([fig1, "--vtk", f"{tmp}/fig1.txt"], "the file must end in .vtp"),
                         ([fig1, "--seed", "-1"], "--seed: Value -1 not in range 0 to 1000000000000000000"),
                         ([tmp], f"{tmp}: is a directory, not an L-system file")):
        p = subprocess.run([BIOTA, "lsystem"] + args, capture_output=True, text=True)
        lines = [l for l in p.stderr.splitlines() if needle in l]
        expect(p.returncode == 2 and len(lines) == 1 and "ERR" not in p.stderr
               and not os.path.exists(f"{tmp}/fig1.txt"), f"lsystem {' '.join(args[1:])}: one line ({p.stderr})")

sys.exit(1 if failures else 0)
