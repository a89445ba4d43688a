#!/usr/bin/env python3
"""Drive `biota` as a user does: check a deck, run the tank on 3 ranks with output and
checkpoints, restart on 2 ranks, stop a run with SIGTERM (what a batch scheduler sends) and find
its checkpoint. Usage: run_cli.py <biota> <mpiexec> <source dir>"""
import glob
import os
import re
import signal
import subprocess
import sys
import tempfile
import time

BIOTA, MPIEXEC, SRC = sys.argv[1:4]
DECK = os.path.join(SRC, "input", "tank.toml")
failures = []


def expect(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)


def run(np_, args, **kw):
    return subprocess.run([MPIEXEC, "-n", str(np_), BIOTA] + args, capture_output=True, text=True,
                          timeout=240, **kw)


with tempfile.TemporaryDirectory() as tmp:
    # The deck's jet and outlet sit at the centre of a 1 m tank: move them onto the small grid
    # (a jet outside the tank is an input error since issue 8).
    small = ["--set", "lbm.nx=24", "--set", "lbm.ny=20", "--set", "lbm.nz=18",
             "--set", "lbm.inlet.center=[0.12, 0.1]", "--set", "lbm.inlet.radius=0.04",
             "--set", "lbm.outlet.center=[0.12, 0.1]", "--set", "lbm.outlet.r_min=0.08",
             "--set", f"output.dir={tmp}/out", "--set", f"checkpoint.dir={tmp}/ckpt",
             "--set", "output.interval=20", "--set", "checkpoint.interval=20",
             "--set", "run.progress_interval=10"]
    p = run(1, ["check", DECK])
    expect(p.returncode == 0 and "OK" in p.stdout, "biota check input/tank.toml")
    # A deck key given quoted or bare on the command line, the scenario too (session 41: the
    # scenario's quotes were kept: 'scenario = ""tank"" is not a known scenario').
    for value in ('"tank"', "tank"):
        p = run(1, ["check", DECK, "--set", f"scenario={value}"])
        expect(p.returncode == 0 and "OK" in p.stdout, f"biota check --set scenario={value}")
    # Every shipped deck checks clean: no key it gives goes unused. A key of another mode (a wall
    # velocity on a face that is not a moving wall) is named in one warning on 2 ranks; exit 0.
    for deck in sorted(glob.glob(os.path.join(SRC, "input", "*.toml"))):
        p = run(1, ["check", deck])
        expect(p.returncode == 0 and "OK" in p.stdout and "warning" not in p.stderr,
               f"biota check {os.path.basename(deck)}: OK, no warning ({p.stderr.strip()[-300:]})")
    p = run(2, ["check", os.path.join(SRC, "input", "wind.toml"),
                "--set", "wind.boundary.x_hi_velocity=[1,0,0]"])
    warnings = [l for l in p.stderr.splitlines() if l.startswith("biota: warning:")]
    expect(p.returncode == 0 and len(warnings) == 1
           and warnings[0].endswith("has no effect; docs/deck-reference.md): wind.boundary.x_hi_velocity"),
           f"an unused key is named once: {warnings}")
    # A directory for the deck, and an empty --restart (an unset "$CKPT" would start from scratch
    # without a word): one line each, exit 2, on 2 ranks.
    for args, needle in ((["run", tmp], f"{tmp}: is a directory, not a deck file"),
                         (["run", DECK, "--restart", ""], '--restart "": give a checkpoint file or')):
        p = run(2, args)
        lines = [l for l in p.stderr.splitlines() if l.startswith("biota: error:")]
        expect(p.returncode == 2 and len(lines) == 1 and needle in lines[0],
               f"biota {' '.join(args[:1])} ... stops with one line: {lines}")
    p = subprocess.run([BIOTA, "--version"], capture_output=True, text=True)
    expect(p.returncode == 0 and "HDF5" in p.stdout and "VTK" in p.stdout
           and "instructions: " in p.stdout, "biota --version")
    # The git revision (or "unknown" outside a clone) names the code in the run and its files.
    m = re.search(r"\(revision (\S+),", p.stdout)
    expect(m is not None, "biota --version names the revision")
    revision = m.group(1) if m else "no revision"

    p = run(3, ["run", DECK, "--set", "run.steps=40"] + small)
    expect(p.returncode == 0, f"tank on 3 ranks exits 0 (got {p.returncode}: {p.stderr[-400:]})")
    expect("[lbm]" in p.stdout and "tau = 0.533" in p.stdout, "effective config printed")
    expect(re.search(r"step\s+40/40\s+t =.*MLUPS.*ETA", p.stdout) is not None, "progress line")
    expect("timing breakdown" in p.stdout and "lbm collide+stream" in p.stdout, "timing table")
    expect(len(glob.glob(f"{tmp}/out/tank_*.h5")) == 3, "3 HDF5 output steps (0, 20, 40)")
    expect(len(glob.glob(f"{tmp}/out/tank_*.xmf")) == 3, "3 XDMF files")
    expect(len(glob.glob(f"{tmp}/out/vtk/tank_000040_*.vti")) == 3, "3 VTK pieces per step")
    with open(f"{tmp}/out/tank.pvd") as f:
        expect(f.read().count("<DataSet") == 3, ".pvd lists 3 steps")
    expect(os.path.exists(f"{tmp}/ckpt/tank_00000020.h5"), "interval checkpoint at step 20")
    expect(not glob.glob(f"{tmp}/ckpt/*.tmp"), "no temporary checkpoint left behind")
    expect(f"revision {revision})" in p.stdout, "the run's first line names the revision")
    for path in (f"{tmp}/out/tank_000040.h5", f"{tmp}/ckpt/tank_00000020.h5"):
        with open(path, "rb") as f:
            data = f.read()
        expect(b"biota_revision" in data and revision.encode() in data,
               f"{os.path.basename(path)} holds the attribute biota_revision = {revision}")

    p = run(2, ["run", DECK, "--set", "run.steps=40", "--restart", f"{tmp}/ckpt/tank_00000020.h5"] + small)
    expect(p.returncode == 0 and "restarted from" in p.stdout and "step 20" in p.stdout,
           f"restart on 2 ranks from step 20 ({p.stderr[-300:]})")
    with open(f"{tmp}/out/tank.pvd") as f:
        expect(f.read().count("<DataSet") == 3, ".pvd still lists 3 steps after the restart")

    # SIGTERM: checkpoint and clean exit.
    proc = subprocess.Popen([MPIEXEC, "-n", "2", BIOTA, "run", DECK, "--set", "run.end_time=1e4",
                             "--set", "output.interval=0", "--set", "checkpoint.interval=0"]
                            + small[:14] + ["--set", f"checkpoint.dir={tmp}/sig"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    time.sleep(4)
    # A scheduler (Slurm) signals every task; mpirun's own status after being signalled is
    # OpenMPI's business, so signal the ranks themselves and require a clean exit of the job.
    ranks = subprocess.run(["pgrep", "-P", str(proc.pid)], capture_output=True, text=True).stdout.split()
    for pid in ranks:
        os.kill(int(pid), signal.SIGTERM)
    out, err = proc.communicate(timeout=60)
    expect(len(ranks) == 2 and proc.returncode == 0,
           f"SIGTERM to both ranks gives a clean exit (ranks {ranks}, exit {proc.returncode})")
    expect("received signal" in out and glob.glob(f"{tmp}/sig/tank_*.h5"),
           "SIGTERM writes a checkpoint")

    # A diverging run stops with exit code 3, naming step, position and the last good checkpoint.
    p = run(2, ["run", DECK, "--set", "lbm.nx=16", "--set", "lbm.ny=16", "--set", "lbm.nz=16", "--set", "lbm.inlet.center=[0.08, 0.08]",
                "--set", "lbm.inlet.radius=0.03", "--set", "lbm.outlet.center=[0.08, 0.08]",
                "--set", "lbm.outlet.r_min=0.05",
                "--set", "lbm.body_force=[0, 0, 3e5]", "--set", "run.steps=2000",
                "--set", "run.health_interval=10", "--set", "checkpoint.interval=5",
                "--set", f"output.dir={tmp}/unstable", "--set", f"checkpoint.dir={tmp}/unstable/c"])
    expect(p.returncode == 3 and "unstable at step" in p.stderr and "m" in p.stderr
           and "last good checkpoint: " + f"{tmp}/unstable/c/tank_" in p.stderr,
           f"unstable run stops with exit 3 and names the checkpoint ({p.stderr.strip()[:300]})")

print(f"{len(failures)} failures")
sys.exit(1 if failures else 0)
