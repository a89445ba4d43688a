#!/usr/bin/env python3
"""In-process A/B instrumentation for the seaweed particle step (docs/performance-seaweed.md,
session 16). A development tool: it edits src/models/plants/seaweed_mechanics.cpp in place and
must be reverted (`git checkout src/models/plants/seaweed_mechanics.cpp`) before committing.

What it adds:
- a global variant flag `g_ab`, 0 or 1 on alternate physics steps (`SeaweedBodies::advance`);
- `steady_clock` sums of `compute_forces` and `advance` per variant, printed by every rank at
  exit as `AB rank R: A cf .. adv .. B cf .. adv .. B/A cf .. adv ..`;
- `g_ab_null` (set by the environment variable AB_NULL) to run both variants on the A path: the
  null test of the method.

The code under test then branches on `g_ab == 1 && !g_ab_null` (take the new path) itself. Run a
restart window, for example (2 ranks, t = 8 to 11 s of cycle 5):

  python3 jobs/dev/seaweed_ab_patch.py && cmake --build build --target biota
  mpirun -np 2 ./build/biota run input/seaweed.toml --set growth.cycles=5 \
    --restart <cycle-5 run>/checkpoints/seaweed_00000480.h5 --set run.end_time=11 \
    --set output.dir=/tmp/ab 2>&1 | grep ^AB
"""
import pathlib
p = pathlib.Path(__file__).resolve().parents[2] / "src/models/plants/seaweed_mechanics.cpp"
s=p.read_text()
s=s.replace('''namespace biota::models::plants {

using particles::kNoId;''','''#include <chrono>
#include <cstdio>
#include <cstdlib>
namespace biota::models::plants {
// TEMP A/B
int g_ab = 0;
const bool g_ab_null = std::getenv("AB_NULL") != nullptr;
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

using particles::kNoId;''')
s=s.replace('''void SeaweedBodies::advance(Real dt) {
  const int ns = p_.substeps;''','''void SeaweedBodies::advance(Real dt) {
  static int calls = 0;
  g_ab = calls++ % 2;
  const auto t_adv = std::chrono::steady_clock::now();
  struct AdvT { std::chrono::steady_clock::time_point t; ~AdvT() { g_ab_adv[g_ab] += std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count(); ++g_ab_n[g_ab]; } } advt{t_adv};
  const int ns = p_.substeps;''')
s=s.replace('''    compute_forces(h);
    // Symplectic''','''    {
      const auto t0 = std::chrono::steady_clock::now();
      compute_forces(h);
      g_ab_cf[g_ab] += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
    // Symplectic''')
p.write_text(s)
