#!/usr/bin/env python3
"""Phase timers for the seaweed particle step (docs/performance-seaweed.md, session 25). A
development tool like seaweed_ab_patch.py: it edits src/models/plants/seaweed_sub_step.cpp in
place and must be reverted (`--revert`, or `git checkout` of the file) before committing. Apply
one of the two tools at a time: both edit the sub-step.

It adds wall-clock marks between the phases of a sub-step and prints, per rank at exit, one line

  PH<rank> body .. hot .. joints .. filter .. contacts .. disp .. ghosts .. integ ..

with the seconds each phase took over the run: body forces, hot-record build, joints (gather,
law, add-back), inner-list filter (check and re-filter), contacts (compaction, law, add-back),
displacement check, ghost refresh (with the skin-check reduction), integration. With blocks
(seaweed.sub_step_block) each phase sums over the blocks. The step's migrations and list
rebuilds are in none of them. For example (2 ranks, t = 20 to 22 s of a
cycle-5 run):

  python3 jobs/dev/seaweed_phase_patch.py && cmake --build build --target biota
  mpirun -np 2 ./build/biota run input/seaweed.toml --set growth.cycles=5 \\
    --restart <cycle-5 run>/checkpoints/seaweed_00001200.h5 --set run.end_time=22 \\
    --set output.dir=/tmp/ph --set checkpoint.interval=0 2>&1 | grep ^PH
"""
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import source_patch  # noqa: E402

p = pathlib.Path(__file__).resolve().parents[2] / "src/models/plants/seaweed_sub_step.cpp"


def mark(k):
    return f"  seaweed_phase_mark({k});  // TEMP phases\n"


HEADER = '''#include "models/plants/seaweed_mechanics.hpp"
// TEMP phases
#include <chrono>
#include <cstdio>
#include <cstdlib>
namespace {
double g_phase_s[10];
std::chrono::steady_clock::time_point g_phase_t;
const char* const g_phase_name[10] = {"body",     "hot",  "joints", "filter", "contacts",
                                      "disp",     "ghosts", "-",    "integ",  "-"};
void seaweed_phase_mark(int k) {
  const auto now = std::chrono::steady_clock::now();
  g_phase_s[k] += std::chrono::duration<double>(now - g_phase_t).count();
  g_phase_t = now;
}
struct PhaseReport {
  ~PhaseReport() {
    char line[512];
    const char* r = std::getenv("OMPI_COMM_WORLD_RANK");
    int o = std::snprintf(line, sizeof line, "PH%s", r ? r : "?");
    for (int k = 0; k < 9; ++k)
      if (g_phase_name[k][0] != '-')
        o += std::snprintf(line + o, sizeof line - o, " %s %.3f", g_phase_name[k], g_phase_s[k]);
    std::fprintf(stderr, "%s\\n", line);
  }
} g_phase_report;
}  // namespace
'''

# (original text, instrumented text); bucket 7 (migration and list rebuild inside the step) and
# 9 (the rest: breaks, loop overhead) are not printed.
EDITS = [
    ('#include "models/plants/seaweed_mechanics.hpp"\n', HEADER),
    ('''    hot_[i] = {x.at(i), v.at(i), w.at(i), rad[i], {qw[i], qx[i], qy[i], qz[i]}, {0, 0}};
''', '''    hot_[i] = {x.at(i), v.at(i), w.at(i), rad[i], {qw[i], qx[i], qy[i], qz[i]}, {0, 0}};
''' + mark(1)),
    ('''  begin_sub_step();
  const Real m''', '''  begin_sub_step();
''' + mark(3) + '''  const Real m'''),
    ('''              span);
''', '''              span);
''' + mark(0)),
    ('''  // Contacts: each pair once per block''', mark(2) + '''  // Contacts: each pair once per block'''),
    ('''      if (mine(b[l])) add(b[l], -f, {r.tbx[l], r.tby[l], r.tbz[l]});
    }
  }
}
''', '''      if (mine(b[l])) add(b[l], -f, {r.tbx[l], r.tby[l], r.tbz[l]});
    }
  }
''' + mark(4) + '''}
'''),
    ('''    integrate_spheres(cols, blk.hi - blk.lo, h, h / m, h / I);
''', '''    integrate_spheres(cols, blk.hi - blk.lo, h, h / m, h / I);
''' + mark(8)),
    ('''  set_.zero_real(a_imp);
''', '''  set_.zero_real(a_imp);
  g_phase_t = std::chrono::steady_clock::now();  // TEMP phases
'''),
    ('''      int flag = local_displacement_exceeded();
      MPI_Request req;''', mark(9) + '''      int flag = local_displacement_exceeded();
''' + mark(5) + '''      MPI_Request req;'''),
    ('''      MPI_Wait(&req, MPI_STATUS_IGNORE);
''', '''      MPI_Wait(&req, MPI_STATUS_IGNORE);
''' + mark(6)),
    ('''    sub_step(h);
''', mark(7) + '''    sub_step(h);
'''),
]

source_patch.apply(p, EDITS, "seaweed_phase_patch.py")
