#!/usr/bin/env python3
"""A stand-in for SLURM's sbatch/scontrol and PBS's qsub, enough to run a Biota batch job end to end
on one machine (tests/regression/batch). Jobs run synchronously, one after another.

  sbatch SCRIPT    run SCRIPT with SLURM_* variables. The time limit falls when the job has printed
                   its first progress line ("step N/M"): --signal=B:SIG@S from the #SBATCH lines
                   sends SIG to the batch shell, and S s later the job's process group is
                   SIGKILLed. Requeued jobs (scontrol requeue) run again with SLURM_RESTART_COUNT+1
                   and the log appended.
  scontrol requeue ID   (inside a job) mark the job for requeue.
  qsub [-v VAR=val] SCRIPT   run SCRIPT with PBS_* variables; at the same progress "limit" SIGTERM
                   (PBS at the walltime), SIGKILL 10 s later. A qsub from inside a job is queued
                   and run when the job ends.
"""
import glob
import os
import re
import signal
import subprocess
import sys
import time

FREEZE_MAX = 5.0  # s the ranks stay frozen at most (a signal may reach a thread as it stops;
# beside another test the trap -> kill -> mpiexec -> rank chain took over 1 s)
KILL_DELAY = 10  # s from PBS's SIGTERM to its SIGKILL (PBS Pro's default kill_delay)
QUEUE = os.environ.get("FAKE_SCHED_DIR", "/tmp") + "/queue"


def job_ranks(root_pid):
    """The Biota rank processes below root_pid (the batch shell): descendants named `biota`."""
    children = {}
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/stat") as f:
                    stat = f.read()
            except OSError:
                continue
            comm = stat[stat.index("(") + 1:stat.rindex(")")]
            ppid = int(stat[stat.rindex(")") + 2:].split()[1])
            children.setdefault(ppid, []).append((int(entry), comm))
    ranks, todo = [], [root_pid]
    while todo:
        for pid, comm in children.get(todo.pop(), []):
            todo.append(pid)
            if comm == "biota":
                ranks.append(pid)
    return ranks


def usr1_pending(pid):
    """True if SIGUSR1 waits in the pending set of pid (thread or process), or pid is gone."""
    bit = 1 << (signal.SIGUSR1 - 1)
    try:
        with open(f"/proc/{pid}/status") as f:
            fields = dict(line.split(":", 1) for line in f if ":" in line)
    except OSError:
        return True
    return any(int(fields.get(k, "0").strip(), 16) & bit for k in ("SigPnd", "ShdPnd"))


def segment_logs(log):
    """The Biota job's own segment logs (jobs/batch/job-lib.sh) beside the scheduler's log."""
    return glob.glob(os.path.join(os.path.dirname(os.path.abspath(log)), "segment_*.log"))


def progress_printed(log, offset, seg_offsets):
    """True once the segment has printed a progress line. Read from Biota's segment log, which it
    writes line by line, as well as from the scheduler's log: the scheduler's copy comes through
    `tail -f`, which polls once a second where inotify is missing, and on a fast host the segment
    finished in that second (CI: one segment, a failed check)."""
    texts = []
    with open(log) as f:
        f.seek(offset)
        texts.append(f.read())
    for path in segment_logs(log):
        try:
            size = os.path.getsize(path)
            with open(path) as f:
                start = seg_offsets.get(path, 0)
                f.seek(start if size >= start else 0)  # a log rewritten from the start
                texts.append(f.read())
        except OSError:
            continue
    return any(re.search(r"^step +\d+/", text, re.M) for text in texts)


def run_job(script, env, log, warn_sig, kill_after):
    """Run one job segment; its "time limit" falls when the job has printed its first progress line
    (a clock in steps, so the limit lands mid-run on a loaded or an idle machine alike): warn_sig to
    the batch shell, SIGKILL to the job's process group kill_after s later if it still runs.

    The ranks are frozen (SIGSTOP) from the moment the limit falls until the batch shell's
    forwarded SIGUSR1 is pending in every rank, or FREEZE_MAX s (a thread caught by the signal
    just as it stops runs the handler first, so nothing is pending): a small run on a fast host
    otherwise finishes the rest of its steps while the signal travels through bash and mpirun
    (one segment, a failed check). Frozen ranks take the signal at their next step."""
    offset = os.path.getsize(log) if os.path.exists(log) else 0
    seg_offsets = {f: os.path.getsize(f) for f in segment_logs(log)}
    with open(log, "a") as out:
        p = subprocess.Popen(["bash", script], env=env, stdout=out, stderr=subprocess.STDOUT,
                             start_new_session=True)
    warned_at = None
    while p.poll() is None:
        time.sleep(0.005)
        if warned_at is None:
            if progress_printed(log, offset, seg_offsets):
                ranks = job_ranks(p.pid)
                for pid in ranks:
                    try:
                        os.kill(pid, signal.SIGSTOP)
                    except ProcessLookupError:
                        pass
                os.kill(p.pid, warn_sig)
                warned_at = time.time()
                while not all(usr1_pending(pid) for pid in ranks) \
                        and time.time() - warned_at < FREEZE_MAX:
                    time.sleep(0.01)
                for pid in ranks:
                    try:
                        os.kill(pid, signal.SIGCONT)
                    except ProcessLookupError:
                        pass
        elif time.time() - warned_at > kill_after:
            os.killpg(p.pid, signal.SIGKILL)
    return p.wait()


def sbatch(args):
    script = args[-1]
    text = open(script).read()
    opt = dict(re.findall(r"^#SBATCH --([\w-]+)=(\S+)", text, re.M))
    m = re.match(r"B:(\w+)@(\d+)", opt["signal"])
    sig, before = getattr(signal, "SIG" + m.group(1)), int(m.group(2))
    ntasks = int(opt.get("nodes", 1)) * int(opt.get("ntasks-per-node", 1))
    jobid = "4242"
    log = opt.get("output", "slurm-%j.out").replace("%j", jobid)
    print(f"Submitted batch job {jobid}")
    marker = QUEUE + ".requeue"
    count, rc = 0, 0
    while True:
        env = dict(os.environ, SLURM_JOB_ID=jobid, SLURM_NTASKS=str(ntasks),
                   SLURM_RESTART_COUNT=str(count), FAKE_IN_JOB="1")
        rc = run_job(script, env, log, sig, before)
        if not os.path.exists(marker):
            break
        os.remove(marker)
        count += 1
    return rc


def scontrol(args):
    if args[:1] != ["requeue"]:
        sys.exit("fake scontrol: only 'requeue' is implemented")
    open(QUEUE + ".requeue", "w").close()
    return 0


def qsub(args):
    env_add = {}
    if "-v" in args:
        for kv in args[args.index("-v") + 1].split(","):
            k, v = kv.split("=", 1)
            env_add[k] = v
    script = args[-1]
    if os.environ.get("FAKE_IN_JOB"):
        with open(QUEUE, "a") as q:
            q.write(repr((script, env_add)) + "\n")
        print("4243.fake")
        return 0
    jobs, rc = [(script, env_add)], 0
    while jobs:
        script, env_add = jobs.pop(0)
        text = open(script).read()
        outdir = re.search(r"^#PBS -o (\S+)", text, re.M).group(1)
        env = dict(os.environ, PBS_JOBID="4243.fake", PBS_O_WORKDIR=os.getcwd(), FAKE_IN_JOB="1",
                   **env_add)
        rc = run_job(script, env, os.path.join(outdir, "pbs.out"), signal.SIGTERM, KILL_DELAY)
        if os.path.exists(QUEUE):
            jobs += [eval(line) for line in open(QUEUE)]
            os.remove(QUEUE)
    return rc


if __name__ == "__main__":
    tool = os.path.basename(sys.argv[0])
    sys.exit({"sbatch": sbatch, "scontrol": scontrol, "qsub": qsub}[tool](sys.argv[1:]))
