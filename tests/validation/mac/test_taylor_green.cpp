// Taylor-Green vortex (2D, periodic, one periodic cell in z): kinetic energy decay against
// exp(-4 nu t) and the spatial order of the velocity error with dt proportional to dx.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <cstdio>
#include <numbers>

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

constexpr double kNu = 0.05, kEnd = 1.0;

struct Result {
  double error, energy_error;
};

Result run(int N) {
  const double pi = std::numbers::pi, L = 2 * pi, dx = L / N;
  MacParams p;
  p.cells = {N, N, 1};
  p.dx = dx;
  for (auto& a : p.boundaries) a[0].type = a[1].type = BoundaryType::kPeriodic;
  p.viscosity = kNu;
  const int steps = 5 * N / 8;  // CFL 0.2 with |u| <= 1 (dt = kEnd / steps ~ 0.2 dx)
  p.fixed_dt = kEnd / steps;
  grid::Decomposition d(MPI_COMM_WORLD, p.cells, {true, true, true});
  core::Timers t;
  MacSolver s(d, p, t);
  const auto lo = d.local_box().lo;
  const auto n = d.local_cells();
  auto exact = [&](int c, int i, int j, double time) {  // face values
    const double x = (lo.x + i + (c == 0 ? 0.0 : 0.5)) * dx;
    const double y = (lo.y + j + (c == 1 ? 0.0 : 0.5)) * dx;
    const double f = std::exp(-2 * kNu * time);
    if (c == 0) return std::sin(x) * std::cos(y) * f;
    if (c == 1) return -std::cos(x) * std::sin(y) * f;
    return 0.0;
  };
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < n.z; ++k)
      for (int j = 0; j < n.y; ++j)
        for (int i = 0; i < n.x; ++i) s.velocity()(i, j, k, c) = exact(c, i, j, 0);
  s.refresh();
  const double e0 = s.kinetic_energy();
  for (int i = 0; i < steps; ++i) s.step();
  EXPECT_NEAR(s.time(), kEnd, 1e-12);
  double err = 0;
  for (int c = 0; c < 2; ++c)
    for (int j = 0; j < n.y; ++j)
      for (int i = 0; i < n.x; ++i)
        err = std::max(err, std::fabs(s.velocity()(i, j, 0, c) - exact(c, i, j, s.time())));
  double g = 0;
  MPI_Allreduce(&err, &g, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  const double ratio = s.kinetic_energy() / e0, theory = std::exp(-4 * kNu * s.time());
  return {g, std::fabs(ratio - theory) / theory};
}
}  // namespace

TEST(TaylorGreen, EnergyDecayAndSpatialOrder) {
  const int sizes[3] = {16, 32, 64};
  Result r[3];
  for (int i = 0; i < 3; ++i) r[i] = run(sizes[i]);
  int rank;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  for (int i = 0; i < 3; ++i) {
    if (rank == 0)
      std::printf(
          "N=%d  max velocity error %.3e  energy-decay error %.3e%s\n", sizes[i], r[i].error,
          r[i].energy_error,
          i ? (" order " + std::to_string(std::log2(r[i - 1].error / r[i].error))).c_str() : "");
  }
  EXPECT_GE(std::log2(r[1].error / r[2].error), 1.8);
  EXPECT_GE(std::log2(r[0].error / r[1].error), 1.8);
  EXPECT_LE(r[2].energy_error, 1e-3);
}
