#!/usr/bin/env python3
"""The benchmark commands given options they cannot run: each stops at once with exit 2 and one
line naming the option and what is allowed, on 1-3 ranks, and never hangs. Before session 41 a
flock case that failed on rank 0 alone (its solo round) left the other ranks waiting for ever,
`bench lbm --size 2000` and `biota_bench_wind --size 3000` ended in std::bad_alloc, an unknown
`--case` or an option of the other benchmark ran without a word, and `biota_bench_wind` ignored
unknown options and read `--size abc` as 0.
Usage: run_bench_bad_options.py <biota> <biota_bench_wind> <mpiexec>"""
import resource
import subprocess
import sys

BIOTA, WIND, MPIEXEC = sys.argv[1:4]


def limit_data():  # the flock's memory check reads RLIMIT_DATA: a deterministic shortfall
    resource.setrlimit(resource.RLIMIT_DATA, (4 << 30, 4 << 30))


# (name, ranks, program, arguments, the error's text, the line's prefix, preexec)
CASES = [
    ("lbm size 0", 1, BIOTA, ["bench", "lbm", "--size", "0"], "--size: Value 0 not in range 1 to 100000", "", None),
    ("lbm size over 3 ranks", 3, BIOTA, ["bench", "lbm", "--size", "2", "--no-peer"],
     "bench lbm: --size = 2 x 2 x 2 cells cannot be split over 3 MPI ranks", "biota: error:", None),
    ("lbm size beyond memory", 2, BIOTA, ["bench", "lbm", "--size", "2000", "--no-peer"],
     "bench lbm: --size 2000 (2000^3 cells) need about", "biota: error:", None),
    ("lbm unknown case", 1, BIOTA, ["bench", "lbm", "--case", "D3Q27/bgk"],
     "--case: D3Q27/bgk not in {D3Q15/bgk,D3Q15/trt,D3Q19/bgk,D3Q19/trt}", "", None),
    ("lbm given a flock option", 2, BIOTA, ["bench", "lbm", "--boids", "1000"],
     "bench lbm: --boids is an option of `biota bench flock` only", "biota: error:", None),
    ("flock given an lbm option", 2, BIOTA, ["bench", "flock", "--size", "50"],
     "bench flock: --size is an option of `biota bench lbm` only", "biota: error:", None),
    ("flock no boids", 1, BIOTA, ["bench", "flock", "--boids", "0"],
     "--boids: Value 0 not in range 1 to 100000000", "", None),
    ("flock reach", 1, BIOTA, ["bench", "flock", "--reach", "5"], "--reach: Value 5 not in range 1 to 4", "", None),
    ("flock box too small", 3, BIOTA, ["bench", "flock", "--boids", "10"],
     "bench flock: --boids 10 gives a 6 m periodic box at 20 boids per perception sphere, under the 3 "
     "perception radii (9 m) a periodic box needs; allowed: at least 39 boids", "biota: error:", None),
    ("flock fails on rank 0 alone", 2, BIOTA, ["bench", "flock", "--boids", "20000000", "--steps", "1"],
     "bench flock --boids 20000000 (rank 0 alone): flock.prey.count = 20000000 prey", "biota: error:",
     limit_data),
    ("wind unknown option", 1, WIND, ["--sizes", "8"], "The following arguments were not expected", "", None),
    ("wind size not a number", 1, WIND, ["--size", "abc"], "--size: Value abc not in range 0 to 100000", "",
     None),
    ("wind no steps", 1, WIND, ["--size", "8", "--steps", "0"], "--steps: Value 0 not in range 1 to 1000000", "",
     None),
    ("wind nothing to run", 1, WIND, ["--size", "0"], "--size 0 runs no step case and no --sweep is given", "",
     None),
    ("wind blocks thinner than the halo", 3, WIND, ["--size", "4", "--steps", "1"],
     "--size = 4 over 3 ranks along axis 1 (3 ranks in all) gives 1-cell rank blocks, thinner than the "
     "2-cell halo", "biota_bench_wind: error:", None),
    ("wind sweep over 3 ranks", 3, WIND, ["--size", "16", "--sweep", "8,2", "--steps", "1"],
     "--sweep = 2 x 2 x 2 cells cannot be split over 3 MPI ranks", "biota_bench_wind: error:", None),
    ("wind size beyond memory", 2, WIND, ["--size", "3000", "--steps", "1"],
     "--size 3000: 3000^3 cells need about", "biota_bench_wind: error:", None),
]

failures = 0
for name, ranks, program, args, needle, prefix, preexec in CASES:
    cmd = [MPIEXEC, "-n", str(ranks)] + (["--oversubscribe"] if ranks > 2 else []) + [program] + args
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=120, preexec_fn=preexec)
    except subprocess.TimeoutExpired:
        print(f"FAIL {name:34s} did not stop within 120 s")
        failures += 1
        continue
    # One line with the message: the program's own error line, or CLI11's line for a parse error.
    hits = [l for l in p.stderr.splitlines() if needle in l]
    own = [l for l in p.stderr.splitlines() if prefix and l.startswith(prefix)]
    ok = p.returncode == 2 and len(hits) == 1 and (not prefix or (len(own) == 1 and hits[0].startswith(prefix)))
    print(f"{'ok  ' if ok else 'FAIL'} {name:34s} exit={p.returncode} "
          f"{hits[0] if hits else p.stderr.strip()[-400:]}")
    failures += not ok
print(f"{len(CASES) - failures}/{len(CASES)} bad benchmark options rejected correctly")
sys.exit(1 if failures else 0)
