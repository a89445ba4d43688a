#!/usr/bin/env python3
"""Feed malformed decks to `biota run` and check: exit code 2, a one-line error naming the key (or
file), and no output written. Usage: run_bad_decks.py <biota> <mpiexec>"""
import os
import subprocess
import sys
import tempfile

BIOTA, MPIEXEC = sys.argv[1], sys.argv[2]

GOOD = """scenario = "tank"
[run]
steps = 2
[output]
dir = "{out}"
[checkpoint]
dir = "{out}/ckpt"
[lbm]
nx = 8
ny = 8
nz = 8
tau = 0.6
"""

FLOCK = """scenario = "flock"
[run]
steps = 2
[output]
dir = "{out}"
[checkpoint]
dir = "{out}/ckpt"
[flock.sandpile]
size = 4
"""

TREE = """scenario = "tree"
[run]
steps = 2
[output]
dir = "{out}"
[checkpoint]
dir = "{out}/ckpt"
[wind]
nx = 8
ny = 4
nz = 10
dx = 1.0
[tree]
positions = [4.0, 2.0, 0.0]
[tree.species1]
lsystem = "{tmp}/paper_fig1.lsys"
derivations = 2
"""

MOSS = """scenario = "moss"
[run]
steps = 2
[output]
dir = "{out}"
[checkpoint]
dir = "{out}/ckpt"
[moss.terrain]
file = "%s"
"""
MOSS_TERRAIN = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "input", "moss",
                            "scene.obj")
MOSS = MOSS % MOSS_TERRAIN
# The shipped seaweed deck: its errors below come at set-up, before the 100^3 tank is allocated.
SEAWEED = open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "input",
                            "seaweed.toml")).read().replace('dir = "out/seaweed"', 'dir = "{out}"')

# (name, deck text or None for a missing file, extra args, substring the message must contain
#  [, MPI ranks, default 2])
CASES = [
    ("syntax error", 'scenario = "tank"\n[run\nsteps = 2\n', [], "syntax"),
    ("unknown key", GOOD + "typo_key = 3\n", [], "typo_key"),
    ("unknown nested key", GOOD.replace("tau = 0.6", "tau = 0.6\ntua = 0.7"), [], "lbm.tua"),
    ("wrong type", GOOD.replace("steps = 2", 'steps = "two"'), [], "run.steps"),
    ("tau at 0.5", GOOD.replace("tau = 0.6", "tau = 0.5"), [], "lbm.tau"),
    ("tau below 0.5", GOOD.replace("tau = 0.6", "tau = 0.3"), [], "lbm.tau"),
    ("negative size", GOOD.replace("nx = 8", "nx = -8"), [], "lbm.nx"),
    ("negative dx", GOOD + "", ["--set", "lbm.dx=-0.01"], "lbm.dx"),
    ("zero dt", GOOD.replace("tau = 0.6", "tau = 0.6\ndt = 0.0"), [], "lbm.dt"),
    ("unknown lattice", GOOD.replace("tau = 0.6", 'tau = 0.6\nlattice = "D2Q9"'), [], "lbm.lattice"),
    ("unknown boundary", GOOD + '[lbm.boundary]\nx_lo = "sticky"\n', [], "lbm.boundary.x_lo"),
    ("half periodic", GOOD + '[lbm.boundary]\nx_lo = "periodic"\n', [], "lbm.boundary.x_hi"),
    ("unknown scenario", GOOD.replace('"tank"', '"ocean"'), [], "scenario"),
    ("missing scenario", GOOD.replace('scenario = "tank"', ""), [], "scenario"),
    ("missing file", None, [], "cannot open deck"),
    ("tau and viscosity", GOOD.replace("tau = 0.6", "tau = 0.6\nviscosity = 1e-6"), [], "lbm.tau"),
    ("Mach too high", GOOD + '[lbm.inlet]\nface = "z_lo"\nspeed = 100.0\nradius = 0.02\n', [], "Mach"),
    ("no run length", GOOD.replace("steps = 2", ""), [], "run.steps"),
    ("unwritable output dir", GOOD.replace('dir = "{out}"', 'dir = "/proc/biota_out"'), [], "output.dir"),
    ("bad --set", GOOD, ["--set", "run.steps=-3"], "run.steps"),
    ("unknown --set key", GOOD, ["--set", "lbm.speed=3"], "lbm.speed"),
    ("missing restart file", GOOD, ["--restart", "/nonexistent/ckpt.h5"], "ckpt.h5"),
    ("list of wrong length", GOOD + '[lbm.inlet]\ncenter = [0.5]\n', [], "lbm.inlet.center"),
    ("out-of-range pulse", GOOD + '[lbm.inlet]\npulse_amplitude = 2.0\n', [], "lbm.inlet.pulse_amplitude"),
    # Issue 8: one line, once, naming the grid keys and the rank count (was one line per rank).
    ("fewer cells than ranks", GOOD.replace("nx = 8\nny = 8\nnz = 8", "nx = 2\nny = 2\nnz = 2"), [],
     "lbm.nx, lbm.ny, lbm.nz = 2 x 2 x 2 cells cannot be split over 3 MPI ranks", 3),
    # Issue 8: an interval of 2^32 became 0 in an int (SIGFPE); every integer key has a range now.
    ("interval overflow", FLOCK, ["--set", "flock.stats_interval=4294967296"], "flock.stats_interval"),
    # Issue 8: geometric keys that select no cell or lie outside the domain (0.08 m tank here).
    ("inlet outside the tank", GOOD + '[lbm.inlet]\nface = "z_lo"\ncenter = [5.0, 5.0]\nradius = 0.02\nspeed = 0.01\n',
     [], "lbm.inlet.center = [5, 5] lies outside the face"),
    ("inlet selecting no cell", GOOD + '[lbm.inlet]\nface = "z_lo"\ncenter = [0.04, 0.04]\nradius = 0.001\nspeed = 0.01\n',
     [], "lbm.inlet.center"),
    ("outlet ring selecting no cell", GOOD + '[lbm.outlet]\nface = "z_lo"\ncenter = [0.04, 0.04]\nr_min = 0.5\n',
     [], "lbm.outlet.center"),
    ("placement box outside", GOOD.replace('"tank"', '"seaweed"').replace("tau = 0.6", "tau = 0.6\ndt = 0.0016666666666666668"),
     ["--set", "seaweed.placement.hi=[0.5, 0.06, 0.06]", "--set", "seaweed.plants=1"], "seaweed.placement.lo"),
    ("predator start outside", FLOCK, ["--set", "flock.predator.start=[500, 5, 5]"], "flock.predator.start"),
    # Issue 8: a grid too large for the machine: one line, needed vs available (was bad_alloc).
    # An end time shorter than half a step selects no step (seconds given to the moss' daily step).
    ("end time selects no step", MOSS, ["--set", "run.end_time=40"],
     "run.end_time = 40.0 s is shorter than half of the scenario's time step (86400 s)"),
    ("grid too large", GOOD, ["--set", "lbm.nx=100000", "--set", "lbm.ny=100000", "--set", "lbm.nz=100000"],
     "lbm.nx x lbm.ny x lbm.nz = 100000 x 100000 x 100000 cells (D3Q15) need about"),
    # Issue 9: the tree scenario's placement, species and contact keys.
    ("tree positions count", TREE, ["--set", "tree.count=2"], "tree.positions"),
    ("tree outside the box", TREE.replace("[4.0, 2.0, 0.0]", "[40.0, 2.0, 0.0]"), [], "tree.positions"),
    ("tree species out of range", TREE, ["--set", "tree.species_of=[2.0]"], "tree.species_of"),
    ("tree taller than the box", TREE, ["--set", "tree.species1.height=20.0"], "tree.species1.height"),
    ("unstable contact stiffness", TREE, ["--set", "tree.contacts=true", "--set",
                                          "tree.contact_stiffness=1e6"], "tree.contact_stiffness"),
    ("missing L-system file", TREE.replace("{tmp}/paper_fig1.lsys", "{tmp}/nope.lsys"), [],
     "tree.species1.lsystem"),
    ("bad L-system grammar", TREE.replace("{tmp}/paper_fig1.lsys", "{tmp}/bad.lsys"), [],
     'tree.species1.lsystem = "{tmp}/bad.lsys" is not a valid L-system: {tmp}/bad.lsys:1:1: '
     "expected an 'axiom:' line"),
    # 73 modules after 2 derivations, 13 after 1: the deck's keys and the most that fit.
    ("tree module cap", TREE, ["--set", "tree.max_modules=50"],
     "tree.species1.derivations = 2: " + "{tmp}/paper_fig1.lsys: derivation 2 of 2 exceeds the "
     "module cap of 50 (tree.max_modules); allowed: at most 1 derivations with this cap"),
    # Issue 12: output.region must select a cell of the domain (0.08 m tank here); region and
    # stride apply to grid fields, not to the flock.
    ("output region outside", GOOD, ["--set", "output.region=[1, 1, 1, 2, 2, 2]"],
     "output.region = [1, 1, 1, 2, 2, 2] selects no cell (x axis: no cell centre in [1, 2] m); the domain is [0, 0.08]"),
    ("output region inverted", GOOD, ["--set", "output.region=[0.05, 0, 0, 0.01, 0.08, 0.08]"],
     "output.region = [0.05, 0, 0, 0.01, 0.08, 0.08] is not a box"),
    ("compression without chunks", GOOD, ["--set", "output.compression=3", "--set", "output.chunk=0"],
     "output.compression = 3 needs chunked datasets"),
    ("flock output stride", FLOCK, ["--set", "output.stride=2"], "output.stride = 2 applies to grid fields"),
    # Issue 10: the moss scenario's terrain and weather keys.
    ("moss terrain missing", MOSS, ["--set", 'moss.terrain.file="/nonexistent/terrain.obj"'],
     "moss.terrain.file = \"/nonexistent/terrain.obj\" cannot be used"),
    # Session 40's edge-of-range runs: these crashed (a segmentation fault), stopped with an internal
    # message naming no key, or ran for hours.
    ("flock take-off outside the box", FLOCK, ["--set", "flock.takeoff.scale=50"],
     "flock.takeoff.scale = 50.0 m puts the take-off pattern outside the box [0, 60] x [0, 60] x "
     "[0, 40] m from flock.takeoff.origin; allowed: at most 40 m from this origin"),
    ("flock radius over a block", FLOCK, ["--set", "flock.boids.perception_radius=1e300"],
     "flock.boids.perception_radius = 1e+300 m is wider than the thinnest rank block (28 m along "
     "axis 1 with 2 ranks along it); allowed: at most 28 m"),
    ("flock radius too fine", FLOCK, ["--set", "flock.boids.perception_radius=1e-9"],
     "cell-list bins of edge radius / flock.domain.bin_reach on a rank; allowed: at least"),
    ("flock prey speed per frame", FLOCK, ["--set", "flock.boids.max_speed=1e300"],
     "flock.boids.max_speed = 1e+300 m/s moves a prey up to"),
    ("flock launch over top speed", FLOCK, ["--set", "flock.takeoff.speed=1e300"],
     "flock.takeoff.speed = 1e+300 m/s is faster than flock.boids.max_speed; allowed: [0, 4] m/s"),
    ("wind solver steps per step", TREE, ["--set", "wind.dt_max=1e-9"],
     "wind.dt_max = 1e-09 gives solver steps of 1e-09 s at the start (its cap)"),
    ("seaweed metamer longer than the tank", SEAWEED, ["--set", "growth.env_max=1e300"],
     "growth.length_max = 0.04 m times the largest environment factor 1e+300 (growth.env_min, "
     "growth.env_max) gives metamers of 4e+298 m, longer than the tank's shortest side 1 m"),
    ("seaweed ghost cutoff over a block", SEAWEED, ["--set", "seaweed.cluster_margin=1e300"],
     "seaweed.cluster_margin = 1e+300 m gives a particle ghost cutoff of 1e+300 m (max(2 seaweed.radius "
     "+ seaweed.cluster_margin, 2 seaweed.spacing) + seaweed.skin), wider than the thinnest rank block "
     "(0.5 m along axis 1 with 2 ranks along it)"),
    # A face naming a vertex past the file's (tinyobjloader passes it through): was a crash.
    ("moss terrain face index", MOSS.replace(MOSS_TERRAIN, "{tmp}/far.obj"), [],
     "far.obj: face 1 (shape '') names vertex 999; allowed: 1 to 3 (the file's vertices)", 3),
    ("moss sunshine above possible", MOSS, ["--set", "moss.weather.sunshine=9.0"], "moss.weather.sunshine"),
    ("moss soil reflectance above 1", MOSS, ["--set", "moss.soil.reflectance=[0.2, 1.5, 0.2]"],
     "moss.soil.reflectance"),
    ("metrics interval overflow", GOOD, ["--set", "run.progress_interval=9223372036854775807"],
     "run.progress_interval"),
    # A pressure-solver option PETSc rejects only when it runs (it slept 10 s on rank 1 and aborted
    # the job from rank 0), on 2 and 3 ranks.
    ("PETSc rejects the solver", TREE, ["--set", 'wind.poisson_options="-poisson_ksp_type preonly"'],
     "PETSc cannot run the pressure solve's options (wind.poisson_options = \"-poisson_ksp_type "
     "preonly\" and the command line after '--'): Running KSP of preonly"),
    ("PETSc rejects the solver, 3 ranks", TREE, ["--", "-poisson_ksp_type", "preonly"],
     "PETSc cannot run the pressure solve's options (wind.poisson_options = \"\"", 3),
    # Blocks thinner than the wind's 2-cell halo (7 ranks: 10 cells along z, the only cut).
    ("wind blocks thinner than the halo", TREE, [],
     ".toml: wind.nz = 10 over 7 ranks along axis 2 (7 ranks in all) gives 1-cell rank "
     "blocks, thinner than the 2-cell halo", 7),
]

failures = 0
with tempfile.TemporaryDirectory() as tmp:
    with open(os.path.join(tmp, "paper_fig1.lsys"), "w") as f:
        f.write("axiom: F\nangle: 20\nF -> F[+F]F[-F][F]\n")
    with open(os.path.join(tmp, "far.obj"), "w") as f:
        f.write("v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 2 999\n")
    with open(os.path.join(tmp, "bad.lsys"), "w") as f:
        f.write("F -> F[+F]F\n")
    for i, (name, text, extra, needle, *np) in enumerate(CASES):
        out = os.path.join(tmp, f"out{i}")
        deck = os.path.join(tmp, f"deck{i}.toml")
        if text is not None:
            with open(deck, "w") as f:
                f.write(text.replace("{out}", out).replace("{tmp}", tmp))
        else:
            deck = os.path.join(tmp, "does_not_exist.toml")
        cmd = [MPIEXEC, "-n", str(np[0] if np else 2), BIOTA, "run", deck] + extra
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
        err_lines = [l for l in p.stderr.splitlines() if l.startswith("biota: error:")]
        needle = needle.replace("{tmp}", tmp)
        ok = p.returncode == 2 and len(err_lines) == 1 and needle in err_lines[0] \
            and not os.path.exists(os.path.join(out, "tank.pvd")) \
            and not os.path.exists(os.path.join(out, "flock_order.csv"))
        print(f"{'ok  ' if ok else 'FAIL'} {name:24s} exit={p.returncode} {err_lines[0] if err_lines else p.stderr.strip()[-300:]}")
        failures += not ok
print(f"{len(CASES) - failures}/{len(CASES)} bad decks rejected correctly")
sys.exit(1 if failures else 0)
