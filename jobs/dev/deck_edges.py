#!/usr/bin/env python3
"""Every numeric deck key at the edges of its allowed range (docs/robustness.md, session 40).

For each scenario's shipped deck and each real or integer key of docs/deck-reference.md with a
range, run the deck with the key at each end of its range (a closed end as is, an open end a
hair inside it, an infinite end as +-1e300) for 2 steps on 2 ranks. A run passes if it exits 0,
or 2 or 3 with exactly one `biota: error:` line. Anything else (a signal, exit 1 with an internal
message, several error lines, no end within the timeout) is printed as BAD and listed at the end.

A development tool, not a test: the whole sweep takes 30-60 minutes on 2 cores. Run it after
`jobs/build.sh`, on an otherwise idle machine (it must not share the cores with a build, which
replaces the binary under the runs):

    jobs/dev/deck_edges.py [scenario ...] [--timeout S]     # default: all six, 90 s per run
"""
import argparse
import os
import re
import shutil
import signal
import subprocess
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DECKS = {'tank': 'input/tank.toml', 'seaweed': 'input/seaweed.toml', 'wind': 'input/wind.toml',
         'tree': 'input/tree.toml', 'flock': 'input/flock.toml', 'moss': 'input/moss.toml'}
# Keys that only choose how long or how often: their edges ask for no step or for hours.
SKIP = {'run.end_time', 'run.steps', 'checkpoint.interval', 'output.interval',
        'run.progress_interval'}
ROW = re.compile(r'\| `([\w.]+)` \| (real|integer) \| [^|]* \| ([\[(])([^,]+), ([^\])]+)([\])]) \|')


def edge_values(typ, lb, lo, hi, rb):
    vals = []
    for v, closed, side in ((lo, lb == '[', -1), (hi, rb == ']', 1)):
        if v in ('inf', '-inf'):
            vals.append('1e300' if side > 0 else '-1e300')
        elif closed:
            vals.append(v)
        elif typ == 'real':
            x = float(v)
            vals.append(repr(x - side * 1e-9 * max(1.0, abs(x))))
    return vals


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('scenarios', nargs='*', metavar='scenario',
                    help=f'one of {", ".join(DECKS)} (default: all)')
    ap.add_argument('--timeout', type=float, default=90, help='seconds per run (> 0)')
    args = ap.parse_args()
    for name in args.scenarios:
        if name not in DECKS:
            ap.error(f'scenario {name!r}: allowed: one of {", ".join(DECKS)}')
    args.scenarios = args.scenarios or list(DECKS)
    if not args.timeout > 0:
        ap.error(f'--timeout {args.timeout}: allowed: > 0 seconds')
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT='1', OMPI_ALLOW_RUN_AS_ROOT_CONFIRM='1')
    reference = open(os.path.join(ROOT, 'docs', 'deck-reference.md')).read()
    sections = re.split(r'^## scenario = "(\w+)"', reference, flags=re.M)
    bad = []
    with tempfile.TemporaryDirectory() as tmp:
        for i in range(1, len(sections), 2):
            scenario, body = sections[i], sections[i + 1]
            if scenario not in args.scenarios:
                continue
            for line in body.splitlines():
                m = ROW.match(line)
                if not m or m.group(1) in SKIP:
                    continue
                key, typ, lb, lo, hi, rb = m.groups()
                for value in edge_values(typ, lb, lo, hi, rb):
                    out = os.path.join(tmp, scenario)
                    shutil.rmtree(out, ignore_errors=True)
                    cmd = ['mpirun', '-np', '2', os.path.join(ROOT, 'build', 'biota'), 'run',
                           os.path.join(ROOT, DECKS[scenario]), '--set', f'{key}={value}',
                           '--set', 'run.steps=2', '--set', f'output.dir={out}',
                           '--set', f'checkpoint.dir={out}/ck']
                    t0 = time.time()
                    # Its own process group, so a timeout kills this run and nothing else.
                    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                                         text=True, env=env, start_new_session=True)
                    try:
                        _, stderr = p.communicate(timeout=args.timeout)
                        rc = p.returncode
                    except subprocess.TimeoutExpired:
                        os.killpg(p.pid, signal.SIGKILL)
                        _, stderr = p.communicate()
                        rc = 'timeout'
                    errors = [l for l in stderr.splitlines() if l.startswith('biota: error')]
                    ok = rc == 0 or (rc in (2, 3) and len(errors) == 1)
                    print(f"{'ok ' if ok else 'BAD'} {scenario} {key}={value} rc={rc} "
                          f"{time.time() - t0:.1f}s {errors[0][:200] if errors else ''}", flush=True)
                    if not ok:
                        bad.append(f'{scenario} {key}={value} rc={rc}: '
                                   f'{(errors or stderr.strip().splitlines()[-1:] or [""])[0][:200]}')
    print(f'BAD: {len(bad)}')
    for b in bad:
        print('  ' + b)
    return 1 if bad else 0


if __name__ == '__main__':
    raise SystemExit(main())
