#!/usr/bin/env python3
"""Run a tiny tank on 2 ranks and open its output with ParaView's readers (pvpython under
postproc/headless.sh, a private Xvfb): XDMF (Xdmf3ReaderS) and the VTK series (PVDReader). Exit 77 (skipped) without ParaView.
Usage: run_paraview_check.py <biota> <mpiexec> <source dir>"""
import os
import shutil
import subprocess
import sys
import tempfile

BIOTA, MPIEXEC, SRC = sys.argv[1:4]
if not shutil.which("pvpython") or not shutil.which("Xvfb"):
    print("SKIPPED: pvpython or Xvfb not found (install paraview, xvfb, xauth)")
    sys.exit(77)

with tempfile.TemporaryDirectory() as tmp:
    p = subprocess.run([MPIEXEC, "-n", "2", BIOTA, "run", os.path.join(SRC, "input", "tank.toml"),
                        "--set", "lbm.nx=24", "--set", "lbm.ny=20", "--set", "lbm.nz=18",
                        "--set", "run.steps=30",
                        "--set", "lbm.inlet.center=[0.12, 0.10]", "--set", "lbm.inlet.radius=0.05",
                        "--set", "lbm.inlet.ramp_time=0", "--set", "lbm.outlet.center=[0.12, 0.10]",
                        "--set", "lbm.outlet.r_min=0.08", "--set", "output.interval=15",
                        "--set", f"output.dir={tmp}", "--set", f"checkpoint.dir={tmp}/ckpt"],
                       capture_output=True, text=True, timeout=240)
    if p.returncode != 0:
        print(p.stdout[-2000:], p.stderr[-2000:])
        sys.exit(1)
    check = os.path.join(os.path.dirname(os.path.abspath(__file__)), "check_output.py")
    p = subprocess.run([os.path.join(SRC, "postproc", "headless.sh"), "pvpython", check, tmp, "24", "20", "18"],
                       capture_output=True, text=True, timeout=240)
    print(p.stdout)
    print(p.stderr[-3000:])
    sys.exit(p.returncode)
