#!/usr/bin/env python3
"""In-process A/B instrumentation for the seaweed particle step (docs/performance-seaweed.md,
session 16). A development tool: it edits src/models/plants/seaweed_sub_step.cpp in place and
must be reverted (`git checkout src/models/plants/seaweed_sub_step.cpp`) before committing.

What it adds:
- a global variant flag `g_ab`, 0 or 1 on alternate physics steps (`SeaweedBodies::advance`);
- sums of the force phases, `begin_sub_step` and `block_forces` (printed as `cf`: the calling
  thread's CPU time: they have no communication, and CPU time
  leaves out the time another process on the core takes) and of `advance` (`steady_clock`: it
  waits in MPI, where CPU time would count the busy-polling) per variant, printed by every rank at
  exit as `AB rank R: A cf .. adv .. B cf .. adv .. B/A cf .. adv ..`. The first 4 physics steps
  after the start are not counted: the first one rebuilds the lists and warms the caches, which
  biased a 60-step null test to B/A 0.95 (session 17);
- `g_ab_null` (set by the environment variable AB_NULL) to run both variants on the A path: the
  null test of the method;
- the environment variable AB_ONLY=0 or 1 to run that variant on every step, for instruction
  counts that do not depend on the load (valgrind --tool=callgrind
  --toggle-collect='*SeaweedBodies::block_forces*', once per variant).

The code under test then branches on `g_ab == 1 && !g_ab_null` (take the new path) itself. Run a
restart window, for example (2 ranks, t = 8 to 11 s of cycle 5):

  python3 jobs/dev/seaweed_ab_patch.py && cmake --build build --target biota
  mpirun -np 2 ./build/biota run input/seaweed.toml --set growth.cycles=5 \
    --restart <cycle-5 run>/checkpoints/seaweed_00000480.h5 --set run.end_time=11 \
    --set output.dir=/tmp/ab 2>&1 | grep ^AB

`--revert` undoes exactly these edits and keeps any other change in the file (the code under
test), so work in progress survives a round of measurement.
"""
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import source_patch  # noqa: E402

p = pathlib.Path(__file__).resolve().parents[2] / "src/models/plants/seaweed_sub_step.cpp"
# (original text, instrumented text)
EDITS = [
    ('''namespace biota::models::plants {

using particles::kNoId;''',
     '''#include <chrono>
#include <cstdio>
#include <ctime>
#include <cstdlib>
namespace biota::models::plants {
// TEMP A/B
int g_ab = 0;
bool g_ab_counted = false;
double thread_seconds() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}
const bool g_ab_null = std::getenv("AB_NULL") != nullptr;
const int g_ab_only = std::getenv("AB_ONLY") ? std::atoi(std::getenv("AB_ONLY")) : -1;
double g_ab_cf[2] = {0, 0}, g_ab_adv[2] = {0, 0};
int g_ab_n[2] = {0, 0};
struct AbReport {
  ~AbReport() {
    const char* r = std::getenv("OMPI_COMM_WORLD_RANK");
    std::fprintf(stderr, "AB rank %s: A cf %.4f adv %.4f (%d)  B cf %.4f adv %.4f (%d)  B/A cf %.4f adv %.4f\\n",
                 r ? r : "?", g_ab_cf[0], g_ab_adv[0], g_ab_n[0], g_ab_cf[1], g_ab_adv[1], g_ab_n[1],
                 g_ab_cf[1] / g_ab_cf[0], g_ab_adv[1] / g_ab_adv[0]);
  }
} g_ab_report;

using particles::kNoId;'''),
    ('''void SeaweedBodies::advance(Real dt) {
  const int ns = p_.substeps;''',
     '''void SeaweedBodies::advance(Real dt) {
  static int calls = 0;
  g_ab = g_ab_only >= 0 ? g_ab_only : calls % 2;
  g_ab_counted = ++calls > 4;
  const auto t_adv = std::chrono::steady_clock::now();
  struct AdvT { std::chrono::steady_clock::time_point t; ~AdvT() { if (!g_ab_counted) return; g_ab_adv[g_ab] += std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count(); ++g_ab_n[g_ab]; } } advt{t_adv};
  const int ns = p_.substeps;'''),
    ('''  begin_sub_step();
  const Real m''',
     '''  {
    const double t0 = thread_seconds();
    begin_sub_step();
    if (g_ab_counted) g_ab_cf[g_ab] += thread_seconds() - t0;
  }
  const Real m'''),
    ('''    block_forces(blk, h);
''',
     '''    {
      const double t0 = thread_seconds();
      block_forces(blk, h);
      if (g_ab_counted) g_ab_cf[g_ab] += thread_seconds() - t0;
    }
'''),
]

source_patch.apply(p, EDITS, "seaweed_ab_patch.py")
