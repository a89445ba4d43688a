#!/usr/bin/env python3
"""Every numeric deck key at the edges of its allowed range (docs/robustness.md, session 40).

For each scenario's shipped deck and each real or integer key of docs/deck-reference.md with a
range, run the deck with the key at each end of its range (a closed end as is, an open end a
hair inside it, an infinite end as +-1e300) for 2 steps on 2 ranks. A run passes if it exits 0,
or 2 or 3 with exactly one `biota: error:` line. Anything else (a signal, exit 1 with an internal
message, several error lines, no end within the timeout) is printed as BAD and listed at the end.

With --lists, the list-of-reals keys instead (session 41): every element at +1e300, every
element at -1e300 and every element 0 for a list of fixed length; the empty list, [1e300] and
[-1e300] for a list of any length. (Non-finite elements and wrong lengths are the schema's.)

A development tool, not a test: the whole sweep takes 30-60 minutes on 2 cores (--lists about
15). Run it after `jobs/build.sh`. It must not share the cores with a build that replaces the
binary under the runs: give it a copy (--biota), or wait.

    jobs/dev/deck_edges.py [scenario ...] [--lists] [--timeout S] [--biota PATH]
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
LIST_ROW = re.compile(r'\| `([\w.]+)` \| list of reals \| [^|]* \| list of (?:(\d+) )?reals \|')


def list_values(length):
    if length:
        n = int(length)
        return ['[' + ', '.join([v] * n) + ']' for v in ('1e300', '-1e300', '0')]
    return ['[]', '[1e300]', '[-1e300]']


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
    ap.add_argument('--lists', action='store_true', help='the list-of-reals keys instead')
    ap.add_argument('--biota', default=os.path.join(ROOT, 'build', 'biota'),
                    help='the binary (default: build/biota)')
    args = ap.parse_args()
    for name in args.scenarios:
        if name not in DECKS:
            ap.error(f'scenario {name!r}: allowed: one of {", ".join(DECKS)}')
    args.scenarios = args.scenarios or list(DECKS)
    if not args.timeout > 0:
        ap.error(f'--timeout {args.timeout}: allowed: > 0 seconds')
    if not (os.path.isfile(args.biota) and os.access(args.biota, os.X_OK)):
        ap.error(f'--biota {args.biota}: not an executable file (build it with jobs/build.sh)')
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
                if args.lists:
                    m = LIST_ROW.match(line)
                    if not m:
                        continue
                    key, values = m.group(1), list_values(m.group(2))
                else:
                    m = ROW.match(line)
                    if not m or m.group(1) in SKIP:
                        continue
                    key, values = m.group(1), edge_values(*m.groups()[1:])
                for value in values:
                    out = os.path.join(tmp, scenario)
                    shutil.rmtree(out, ignore_errors=True)
                    cmd = ['mpirun', '-np', '2', args.biota, 'run',
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
