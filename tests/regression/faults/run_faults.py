#!/usr/bin/env python3
"""Fault suite (docs/robustness.md). Drives `biota` with the test-only hook BIOTA_TEST_FAIL:
1. a failure injected on one rank at each phase (step, health check, output, checkpoint,
   end of run, checkpoint/output close) ends the job with the message once and exit != 0, and so
   does a full disk, without a partial file;
2. a restart refuses a changed deck, another scenario, a truncated or non-HDF5 file and a newer
   format, each with one line; `--restart latest` skips .tmp and incomplete files;
3. SIGTERM at a random step (seeded, printed) on 2 and 3 ranks writes a checkpoint, exits 0, and
   the restart continues bitwise to the uninterrupted result;
4. SIGTERM at a step whose interval checkpoint is just written stops without writing it again.
Hangs are caught by the subprocess timeout (and the CTest timeout).
Usage: run_faults.py <biota> <mpiexec> <source dir> <h5_tool>"""
import glob
import os
import random
import shutil
import subprocess
import sys
import tempfile

BIOTA, MPIEXEC, SRC, H5TOOL = sys.argv[1:5]
TANK = os.path.join(SRC, "input", "tank.toml")
FLOCK = os.path.join(SRC, "input", "flock.toml")
failures = []


def expect(cond, what):
    print(("ok   " if cond else "FAIL ") + what, flush=True)
    if not cond:
        failures.append(what)


def run(np_, deck, args, fail=None):
    env = dict(os.environ, BIOTA_ERROR_GRACE="3")
    env.pop("BIOTA_TEST_FAIL", None)
    if fail:
        env["BIOTA_TEST_FAIL"] = fail
    try:
        return subprocess.run([MPIEXEC, "-n", str(np_), BIOTA, "run", deck] + args,
                              capture_output=True, text=True, timeout=90, env=env)
    except subprocess.TimeoutExpired:
        return subprocess.CompletedProcess([], -999, "", "HANG (timeout 90 s)")


def errors(p):
    return [l for l in p.stderr.splitlines() if l.startswith("biota: error:")]


with tempfile.TemporaryDirectory() as tmp:
    def small(name, extra=()):
        # The deck's jet and outlet sit at the centre of a 1 m tank: move them onto the small grid.
        return ["--set", "lbm.nx=16", "--set", "lbm.ny=16", "--set", "lbm.nz=12",
                "--set", "lbm.inlet.center=[0.08, 0.08]", "--set", "lbm.inlet.radius=0.03",
                "--set", "lbm.outlet.center=[0.08, 0.08]", "--set", "lbm.outlet.r_min=0.06",
                "--set", f"output.dir={tmp}/{name}/out", "--set", f"checkpoint.dir={tmp}/{name}/ck",
                "--set", "run.progress_interval=10", "--set", "run.health_interval=5",
                "--set", "checkpoint.interval=10", "--set", "run.steps=20"] + list(extra)

    # --- 1. one error path: (hook, ranks, exit code, text in the message)
    cases = [("step@1@7", 2, 1, "before step 7"),       # rank 1 leaves the halo exchange
             ("step_after@2@7", 3, 1, "after step 7"),
             ("health@1@10", 2, 3, "LBM unstable at step 10"),
             ("output@1@20", 2, 1, "in output at step 20"),
             ("checkpoint@0@10", 3, 1, "in checkpoint at step 10"),
             ("checkpoint_close@1", 2, 1, "the partial file was removed"),
             ("output_close@1", 2, 1, "the partial file was removed"),
             ("end@1", 2, 1, "in end at step 20")]
    for hook, np_, code, text in cases:
        p = run(np_, TANK, small(hook), hook)
        e = errors(p)
        expect(p.returncode == code and len(e) == 1 and text in e[0],
               f"{hook} on {np_} ranks: exit {p.returncode} (want {code}), message once: {e}")
        if hook == "checkpoint_close@1":
            expect(not os.listdir(f"{tmp}/{hook}/ck"),
                   f"failed checkpoint close leaves no file ({os.listdir(f'{tmp}/{hook}/ck')})")
        if hook == "output_close@1":
            expect(not glob.glob(f"{tmp}/{hook}/out/*.h5"), "failed output close leaves no .h5")
        if hook == "output@1@20":
            expect(f"last good checkpoint: {tmp}/{hook}/ck/tank_00000010.h5" in p.stderr,
                   "the last good checkpoint is named")
    # A full disk (the test hook makes rank 0 see no free space): every rank stops before the
    # write, with one line naming the file, and the partial file is removed (a real full disk:
    # docs/robustness.md).
    for np_ in (2, 3):
        p = run(np_, TANK, small(f"full{np_}"), "disk_full@0")
        e = errors(p)
        expect(p.returncode == 1 and len(e) == 1 and "MB free" in e[0] and "tank_000000.h5" in e[0]
               and "aborting" not in p.stderr,
               f"full disk on {np_} ranks: exit {p.returncode}, message once, no abort: {e}")
        expect(not glob.glob(f"{tmp}/full{np_}/out/*.h5*"), "a full disk leaves no .h5")
    # The flock's health check is local to each rank: a NaN on one rank must still stop all.
    p = run(2, FLOCK, ["--set", "run.end_time=0.5", "--set", "run.health_interval=5",
                       "--set", f"output.dir={tmp}/flock/out", "--set", f"checkpoint.dir={tmp}/flock/ck"],
            "health@1@5")
    e = errors(p)
    expect(p.returncode == 3 and len(e) == 1 and "non-finite at step 5" in e[0],
           f"flock NaN on one rank: exit {p.returncode}, {e or p.stderr[-300:]}")
    # A signal reaching one rank after the last step's agreement: no hang, one end checkpoint.
    p = run(2, TANK, small("late"), "late_signal@1@20")
    expect(p.returncode == 0 and "end of run" in p.stdout,
           f"late signal on one rank: exit {p.returncode} {p.stderr[-200:]}")

    # --- 2. restart checks
    base = small("base")
    p = run(2, TANK, base)
    ck10 = f"{tmp}/base/ck/tank_00000010.h5"
    expect(p.returncode == 0 and os.path.exists(ck10), "base run writes checkpoints")
    bad = [("changed tau", ["--set", "lbm.tau=0.55"], ck10, "lbm.tau = 0.533 in the checkpoint"),
           ("changed grid", ["--set", "lbm.nx=20"], ck10, "lbm.nx = 16 in the checkpoint"),
           ("changed seed", ["--set", "seed=7"], ck10, "seed = 12345 in the checkpoint")]
    with open(f"{tmp}/notes.h5", "w") as f:
        f.write("not an HDF5 file\n")
    with open(ck10, "rb") as f:
        data = f.read()
    with open(f"{tmp}/truncated.h5", "wb") as f:
        f.write(data[: len(data) // 2])
    shutil.copy(ck10, f"{tmp}/newer.h5")
    subprocess.run([H5TOOL, "set-int", f"{tmp}/newer.h5", "biota_checkpoint_format", "99"], check=True)
    bad += [("non-HDF5 file", [], f"{tmp}/notes.h5", "not a readable HDF5 file"),
            ("truncated file", [], f"{tmp}/truncated.h5", "not a readable HDF5 file"),
            ("newer format", [], f"{tmp}/newer.h5", "format 99 is newer"),
            ("output file", [], f"{tmp}/base/out/tank_000020.h5", "not a biota checkpoint")]
    pf = run(1, FLOCK, ["--set", "run.end_time=0.1", "--set", f"output.dir={tmp}/fl/out",
                        "--set", f"checkpoint.dir={tmp}/fl/ck"])
    fck = glob.glob(f"{tmp}/fl/ck/flock_*.h5")
    expect(pf.returncode == 0 and fck, "flock run writes a checkpoint")
    if fck:
        bad.append(("other scenario", [], fck[0], "checkpoint of scenario 'flock'"))
    for name, extra, path, text in bad:
        p = run(2, TANK, base + ["--restart", path] + extra)
        e = errors(p)
        expect(p.returncode == 2 and len(e) == 1 and text in e[0],
               f"restart, {name}: exit {p.returncode}, {e or p.stderr[-300:]}")
    p = run(2, TANK, base + ["--set", "run.steps=30", "--set", "output.interval=5", "--restart", ck10])
    expect(p.returncode == 0, f"restart may change run.steps and output.interval ({p.stderr[-200:]})")
    # latest: a .tmp and an incomplete (unreadable) file never count.
    open(f"{tmp}/base/ck/tank_00000090.h5.tmp", "w").write("partial")
    open(f"{tmp}/base/ck/tank_00000080.h5", "w").write("partial")
    p = run(3, TANK, base + ["--set", "run.steps=40", "--restart", "latest"])
    expect(p.returncode == 0 and f"restarted from {tmp}/base/ck/tank_00000030.h5" in p.stdout,
           f"--restart latest picks tank_00000030.h5 ({p.stderr[-300:]})")
    p = run(2, TANK, small("empty") + ["--restart", "latest"])
    e = errors(p)
    expect(p.returncode == 2 and len(e) == 1 and "checkpoint.dir" in e[0],
           f"--restart latest with no checkpoint: {e}")
    # Without checkpoint.dir (the decks' default) checkpoints go to <output.dir>/checkpoints, so
    # two runs with different output directories keep apart, and `latest` finds them there.
    args = small("own")
    own = [a for k, v in zip(args[::2], args[1::2]) if not v.startswith("checkpoint.dir=")
           for a in (k, v)]
    p = run(2, TANK, own)
    expect(p.returncode == 0 and os.path.exists(f"{tmp}/own/out/checkpoints/tank_00000020.h5")
           and not os.path.exists(f"{tmp}/own/ck"),
           f"default checkpoint.dir is <output.dir>/checkpoints ({p.stderr[-200:]})")
    p = run(3, TANK, own + ["--set", "run.steps=30", "--restart", "latest"])
    expect(p.returncode == 0
           and f"restarted from {tmp}/own/out/checkpoints/tank_00000020.h5" in p.stdout,
           f"--restart latest looks in <output.dir>/checkpoints ({p.stderr[-300:]})")
    blocked = [a.replace(f"{tmp}/own/", f"{tmp}/blocked/") for a in own]
    os.makedirs(f"{tmp}/blocked/out")
    open(f"{tmp}/blocked/out/checkpoints", "w").write("a file, not a directory")
    p = run(3, TANK, blocked)
    e = errors(p)
    expect(p.returncode == 2 and len(e) == 1 and f"({tmp}/blocked/out/checkpoints)" in e[0],
           f"default checkpoint directory unusable: one line naming it ({e})")

    # --- 3. SIGTERM at a random step, restart continues bitwise.
    seed = int(os.environ.get("BIOTA_FAULT_SEED", random.SystemRandom().randrange(1 << 30)))
    rng = random.Random(seed)
    print(f"fault suite seed {seed} (set BIOTA_FAULT_SEED to repeat)")
    N = 40
    ref = small("ref", ["--set", f"run.steps={N}", "--set", "checkpoint.interval=0"])
    p = run(1, TANK, ref)
    expect(p.returncode == 0, "uninterrupted reference run")
    for np_ in (2, 3):
        s = rng.randrange(3, N - 3)
        name = f"sig{np_}"
        # The scheduler's signal reaches rank 0 at step s and the last rank one step later.
        args = small(name, ["--set", f"run.steps={N}", "--set", "checkpoint.interval=0"])
        p = run(np_, TANK, args, f"sigterm@0@{s},sigterm@{np_ - 1}@{s + 1}")
        ck = f"{tmp}/{name}/ck/tank_{s:08d}.h5"
        expect(p.returncode == 0 and "received signal 15" in p.stdout and os.path.exists(ck),
               f"SIGTERM at step {s} on {np_} ranks: exit {p.returncode}, checkpoint {ck}")
        p = run(np_, TANK, args + ["--restart", "latest"])
        final = f"{tmp}/{name}/ck/tank_{N:08d}.h5"
        same = subprocess.run([H5TOOL, "same", f"{tmp}/ref/ck/tank_{N:08d}.h5", final,
                               "/fields/lbm_populations"], capture_output=True, text=True)
        expect(p.returncode == 0 and same.returncode == 0,
               f"restart on {np_} ranks continues bitwise: {same.stdout.strip()}")

    # --- 4. SIGTERM at a step that writes an interval checkpoint: that file stands, no second write.
    args = small("sigck", ["--set", f"run.steps={N}", "--set", "checkpoint.interval=10"])
    p = run(2, TANK, args, "sigterm@0@20")
    ck = f"{tmp}/sigck/ck/tank_00000020.h5"
    writes = [l for l in p.stdout.splitlines() if l.startswith("checkpoint (")]
    expect(p.returncode == 0 and os.path.exists(ck) and len(writes) == 3
           and writes[1].startswith("checkpoint (interval) written") and ck in writes[1]
           and writes[2].startswith("checkpoint (signal) written") and ck in writes[2]
           and "at this step already" in writes[2]
           and not glob.glob(f"{tmp}/sigck/ck/tank_0000003*.h5"),
           f"SIGTERM at an interval checkpoint's step: step 20 written once, exit 0 ({writes})")
    p = run(2, TANK, args + ["--restart", "latest"])
    same = subprocess.run([H5TOOL, "same", f"{tmp}/ref/ck/tank_{N:08d}.h5",
                           f"{tmp}/sigck/ck/tank_{N:08d}.h5", "/fields/lbm_populations"],
                          capture_output=True, text=True)
    expect(p.returncode == 0 and same.returncode == 0,
           f"restart from it continues bitwise: {same.stdout.strip()}")

print(f"{len(failures)} failures")
sys.exit(1 if failures else 0)
