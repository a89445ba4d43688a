#!/usr/bin/env python3
"""The batch templates end to end without a scheduler (fake sbatch/srun/scontrol/qsub in fake-bin/):
a small tank on 2 ranks through jobs/submit.sh, SLURM and PBS; each job is stopped by its time
limit mid-run (warning signal -> checkpoint), requeued, continued from the newest checkpoint until
run.end_time; the final fields must equal an uninterrupted run bit for bit.
Usage: run_batch_requeue.py <biota> <mpiexec> <source dir>"""
import filecmp
import glob
import os
import subprocess
import sys
import tempfile

BIOTA, MPIEXEC, SRC = sys.argv[1:4]
HERE = os.path.dirname(os.path.abspath(__file__))
SETS = ["--set", "lbm.nx=24", "--set", "lbm.ny=20", "--set", "lbm.nz=18",
        "--set", "lbm.inlet.center=[0.12, 0.10]", "--set", "lbm.inlet.radius=0.05",
        "--set", "lbm.inlet.ramp_time=0", "--set", "lbm.outlet.center=[0.12, 0.10]",
        "--set", "lbm.outlet.r_min=0.08", "--set", "run.end_time=30", "--set", "output.interval=0",
        "--set", "run.progress_interval=5000"]
fail = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what, flush=True)
    if not cond:
        fail.append(what)


def final_pieces(run_dir):
    return sorted(glob.glob(os.path.join(run_dir, "vtk", "tank_*_000[01].vti")))[-2:]


with tempfile.TemporaryDirectory() as tmp:
    ref = os.path.join(tmp, "ref")
    p = subprocess.run([MPIEXEC, "-n", "2", BIOTA, "run", os.path.join(SRC, "input", "tank.toml")]
                       + SETS + ["--set", f"output.dir={ref}", "--set", f"checkpoint.dir={ref}/ck"],
                       capture_output=True, text=True, timeout=600)
    check(p.returncode == 0, f"uninterrupted run exits 0 ({p.returncode})")
    env = dict(os.environ, PATH=os.path.join(HERE, "fake-bin") + ":" + os.environ["PATH"],
               FAKE_MPIEXEC=MPIEXEC, FAKE_SCHED_DIR=tmp)
    # The fake schedulers' limit falls at each segment's first progress line (every 5000 steps of
    # 18000), so every segment but the last is cut mid-run; SIGKILL follows 30 s (SLURM, --margin)
    # or 10 s (PBS) later. PBS's own deadline (1 h) does not fire here. The fake scheduler freezes
    # the ranks until the forwarded signal is pending in each. With 1800 steps (0.1 s) a segment
    # could still finish before the poller, starved beside another test, saw the progress line
    # (2 of 3 runs beside bad_decks); 18000 steps leave the first segment ~0.7 s after it.
    for sched, time_limit in (("slurm", "00:10:00"), ("pbs", "01:00:00")):
        run_dir = os.path.join(tmp, sched)
        cmd = [os.path.join(SRC, "jobs", "submit.sh"), sched, os.path.join(SRC, "input", "tank.toml"),
               "--nodes", "1", "--tasks-per-node", "2", "--time", time_limit, "--margin", "30",
               "--requeues", "30", "--run-dir", run_dir]
        dry = subprocess.run(cmd + ["--dry-run", "--"] + SETS, capture_output=True, text=True, env=env)
        cmd += ["--"] + SETS
        check(dry.returncode == 0 and not os.path.exists(run_dir)
              and ("#SBATCH --signal=B:TERM@30" in dry.stdout or "#PBS -l walltime=" in dry.stdout),
              f"{sched}: --dry-run prints the script and writes nothing")
        p = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=900)
        logs = "".join(open(f).read() for f in glob.glob(os.path.join(run_dir, "*.out")))
        segs = len(glob.glob(os.path.join(run_dir, "segment_*.log")))
        if p.returncode != 0 or segs < 2:
            print(p.stdout[-3000:], p.stderr[-3000:], logs[-3000:])
        check(p.returncode == 0, f"{sched}: job chain exits 0 ({p.returncode})")
        check(segs >= 2 and "checkpoint (signal) written" in logs,
              f"{sched}: stopped by the time limit and requeued ({segs} segments)")
        check("run complete after" in logs, f"{sched}: the last segment reached run.end_time")
        a, b = final_pieces(ref), final_pieces(run_dir)
        same = len(a) == 2 and [os.path.basename(x) for x in a] == [os.path.basename(x) for x in b] \
            and all(filecmp.cmp(x, y, shallow=False) for x, y in zip(a, b))
        check(same, f"{sched}: final fields equal the uninterrupted run bitwise ({[os.path.basename(x) for x in b]})")
sys.exit(1 if fail else 0)
