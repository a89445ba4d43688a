// MAC solver on 1, 2, 3 ranks: divergence after projection, decomposition invariance against a
// one-rank run inside the same job, and restart continuation from the solver state.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "gather_fields.hpp"
#include "linalg/petsc_environment.hpp"
#include "solvers/mac/mac_solver.hpp"

using namespace biota;
using namespace biota::solvers::mac;

namespace {
class PetscEnv : public ::testing::Environment {
 public:
  void TearDown() override { linalg::finalize(); }
};
const auto* env = ::testing::AddGlobalTestEnvironment(new PetscEnv);

int world_rank() {
  int r;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}

/// Wind over rough ground past a block: log inflow at x_lo, convective outflow at x_hi,
/// periodic y, ground below, free slip on top. Uneven cell counts for uneven splits.
MacParams wind_case() {
  MacParams p;
  p.cells = {23, 10, 12};
  p.dx = 0.5;
  auto& b = p.boundaries;
  b[0][0].type = BoundaryType::kInflow;
  b[0][1].type = BoundaryType::kConvectiveOutflow;
  b[1][0].type = b[1][1].type = BoundaryType::kPeriodic;
  b[2][0].type = BoundaryType::kGround;
  b[2][1].type = BoundaryType::kFreeSlip;
  p.inflow.kind = InflowProfile::kLog;
  p.inflow.speed = 5;
  p.inflow.reference_height = 3;
  p.viscosity = 1e-2;
  p.solid = [](const core::Index3& c) {
    return c.x >= 6 && c.x < 9 && c.y >= 3 && c.y < 6 && c.z < 5;
  };
  p.poisson_options = "-poisson_ksp_rtol 1e-13";
  return p;
}

std::array<bool, 3> periodic_of(const MacParams& p) {
  std::array<bool, 3> per;
  for (int a = 0; a < 3; ++a) per[a] = p.boundaries[a][0].type == BoundaryType::kPeriodic;
  return per;
}

double max_rel_diff(const std::vector<double>& a, const std::vector<double>& b, long long cells) {
  // velocity relative to max |u|, pressure relative to max |p|
  double du = 0, su = 0, dp = 0, sp = 0;
  for (long long i = 0; i < 3 * cells; ++i)
    du = std::max(du, std::fabs(a[i] - b[i])), su = std::max(su, std::fabs(b[i]));
  for (long long i = 3 * cells; i < 4 * cells; ++i)
    dp = std::max(dp, std::fabs(a[i] - b[i])), sp = std::max(sp, std::fabs(b[i]));
  return std::max(du / su, dp / sp);
}
}  // namespace

TEST(Mac, ProjectionLeavesNoDivergence) {
  // Random velocities in a closed box with an obstacle (pure Neumann + solid null space), and
  // in the open wind case; after one projection the divergence must be at solver precision.
  // Variant 2: the paper's one-stage Euler scheme on the open case.
  for (int variant = 0; variant < 3; ++variant) {
    MacParams p = wind_case();
    if (variant == 2) p.scheme = TimeScheme::kEuler;
    if (variant == 0)
      for (auto& a : p.boundaries) a[0].type = a[1].type = BoundaryType::kNoSlip;
    p.poisson_options = "";  // the default tolerance
    grid::Decomposition d(MPI_COMM_WORLD, p.cells, periodic_of(p));
    core::Timers t;
    MacSolver s(d, p, t);
    std::mt19937 gen(1234 + d.rank());
    std::uniform_real_distribution<double> U(-1, 1);
    auto& u = s.velocity();
    const auto n = d.local_cells();
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < n.z; ++k)
        for (int j = 0; j < n.y; ++j)
          for (int i = 0; i < n.x; ++i) u(i, j, k, c) += U(gen);
    s.refresh();
    const double before = s.relative_divergence();
    s.project_initial();
    const double after = s.relative_divergence();
    if (world_rank() == 0)
      std::printf("variant %d: relative divergence %.3e -> %.3e\n", variant, before, after);
    EXPECT_GT(before, 0.1);
    EXPECT_LE(after, 1e-9);
    // And after time steps.
    for (int st = 0; st < 3; ++st) {
      s.step();
      EXPECT_LE(s.last_stats().max_divergence, 1e-9);
    }
  }
}

TEST(Mac, DefaultStopMeetsDivergenceGoal) {
  // The default Poisson stop is the divergence target itself (MacParams::divergence_target,
  // 1e-10): every projection of the wind case must leave a relative divergence <= 1e-10.
  MacParams p = wind_case();
  p.poisson_options = "";
  grid::Decomposition d(MPI_COMM_WORLD, p.cells, periodic_of(p));
  core::Timers t;
  MacSolver s(d, p, t);
  s.project_initial();
  EXPECT_LE(s.relative_divergence(), 1e-10);
  for (int st = 0; st < 6; ++st) {
    s.step();
    if (world_rank() == 0)
      std::printf("step %d: relative divergence %.3e, %d Poisson iterations\n", st,
                  s.last_stats().max_divergence, s.last_stats().poisson_iterations);
    EXPECT_LE(s.last_stats().max_divergence, 1e-10);
  }
}

TEST(Mac, SameFieldsOnOneRank) {
  // The default pressure solve (CG + the geometric multigrid, reproducible sums) gives the same
  // bits on any decomposition; the case's cell counts split unevenly, at odd cells.
  MacParams p = wind_case();
  p.poisson_options = "";
  const int steps = 8;
  // The run on all ranks of this job.
  grid::Decomposition d(MPI_COMM_WORLD, p.cells, periodic_of(p));
  core::Timers t;
  MacSolver s(d, p, t);
  s.project_initial();
  for (int i = 0; i < steps; ++i) s.step();
  auto many = gather_global_fields(s, MPI_COMM_WORLD);
  // The same run on rank 0 alone.
  MPI_Comm solo;
  MPI_Comm_split(MPI_COMM_WORLD, world_rank() == 0 ? 0 : MPI_UNDEFINED, 0, &solo);
  if (solo != MPI_COMM_NULL) {
    {
      grid::Decomposition d1(solo, p.cells, periodic_of(p));
      MacSolver s1(d1, p, t);
      s1.project_initial();
      for (int i = 0; i < steps; ++i) s1.step();
      auto one = gather_global_fields(s1, solo);
      const double diff = max_rel_diff(many, one, p.cells.product());
      int size;
      MPI_Comm_size(MPI_COMM_WORLD, &size);
      std::printf("%d ranks vs 1 rank after %d steps: max relative difference %.3e (t = %.4f)\n",
                  size, steps, diff, s1.time());
      EXPECT_EQ(diff, 0.0);
    }
    MPI_Comm_free(&solo);
  }
}

TEST(Mac, RestartContinues) {
  MacParams p = wind_case();
  grid::Decomposition d(MPI_COMM_WORLD, p.cells, periodic_of(p));
  core::Timers t;
  MacSolver a(d, p, t);
  a.project_initial();
  for (int i = 0; i < 5; ++i) a.step();
  // Snapshot what a checkpoint stores: owned faces, high boundary faces, pressure, clock.
  grid::Field<double> u = a.velocity(), phi = a.pressure();
  auto rows = a.boundary_face_rows();
  std::vector<double> all_rows;
  {
    int n = static_cast<int>(rows.size()), size;
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    std::vector<int> counts(size), displs(size);
    MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
    int tot = 0;
    for (int r = 0; r < size; ++r) displs[r] = tot, tot += counts[r];
    all_rows.resize(tot);
    MPI_Allgatherv(rows.data(), n, MPI_DOUBLE, all_rows.data(), counts.data(), displs.data(),
                   MPI_DOUBLE, MPI_COMM_WORLD);
  }
  const double t0 = a.time();
  for (int i = 0; i < 5; ++i) a.step();

  MacSolver b(d, p, t);
  const auto n = d.local_cells();
  grid::Field<double> ub(n, 3, 2), pb(n, 1, 2);
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < n.z; ++k)
      for (int j = 0; j < n.y; ++j)
        for (int i = 0; i < n.x; ++i) b.velocity()(i, j, k, c) = u(i, j, k, c);
  for (int k = 0; k < n.z; ++k)
    for (int j = 0; j < n.y; ++j)
      for (int i = 0; i < n.x; ++i) b.pressure()(i, j, k) = phi(i, j, k);
  b.set_boundary_face_rows(all_rows);
  b.set_clock(t0, 5);
  b.refresh();
  for (int i = 0; i < 5; ++i) b.step();
  EXPECT_EQ(b.step_index(), 10);
  EXPECT_NEAR(b.time(), a.time(), 1e-12 * a.time());
  auto ga = gather_global_fields(a, MPI_COMM_WORLD), gb = gather_global_fields(b, MPI_COMM_WORLD);
  if (world_rank() == 0) {
    const double diff = max_rel_diff(gb, ga, p.cells.product());
    std::printf("restart: max relative difference %.3e\n", diff);
    EXPECT_EQ(diff, 0.0);  // the same bits (the explicit rtol of wind_case() included)
  }
}
