// Spreading conserves momentum to round-off across ranks (ghost cells summed back), and
// interpolation reproduces linear fields exactly.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>

#include "core/rng.hpp"
#include "coupling/trilinear_coupling.hpp"
#include "grid/halo_exchange.hpp"
#include "particles/particle_comm.hpp"

using namespace biota;
using core::Vec3;

class Coupling : public ::testing::TestWithParam<std::array<bool, 3>> {};

TEST_P(Coupling, SpreadConservesMomentumAndInterpolationIsExactForLinearFields) {
  const auto periodic = GetParam();
  const double dx = 0.01;
  grid::Decomposition decomp(MPI_COMM_WORLD, {13, 11, 12}, periodic);
  particles::ParticleComm pc(decomp, dx);
  coupling::TrilinearCoupling tc(decomp, dx);
  grid::Field<double> force(decomp.local_cells(), 3, 1, 0.0), vel(decomp.local_cells(), 3, 1, 0.0);
  grid::HaloExchange fh(decomp, force), vh(decomp, vel);
  // Particles everywhere in my box, including the wall-adjacent half cells.
  Vec3 local{}, mine{};
  const int n = 500;
  for (int k = 0; k < n; ++k) {
    core::Rng r(3, decomp.rank() * n + k, 0, core::RngPurpose::kTest);
    Vec3 p, f{r.uniform(-1, 1), r.uniform(-1, 1), r.uniform(-1, 1)};
    for (int d = 0; d < 3; ++d) p[d] = r.uniform(pc.lo()[d], pc.hi()[d]);
    tc.spread(force, tc.stencil(p), f);
    mine += f;
  }
  fh.reverse_sum();
  const auto c = decomp.local_cells();
  for (int k = 0; k < c.z; ++k)
    for (int j = 0; j < c.y; ++j)
      for (int i = 0; i < c.x; ++i)
        for (int d = 0; d < 3; ++d) local[d] += force(i, j, k, d);
  double sums[6] = {local.x, local.y, local.z, mine.x, mine.y, mine.z};
  MPI_Allreduce(MPI_IN_PLACE, sums, 6, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  for (int d = 0; d < 3; ++d) EXPECT_NEAR(sums[d], sums[3 + d], 1e-11) << "axis " << d;

  // Linear field u = A x + b, sampled at cell centres; exact away from wall half-cells and
  // periodic seams.
  auto u = [](const Vec3& x) { return Vec3{1 + 2 * x.x - x.y, 3 * x.z + 0.5, x.x + x.y + x.z}; };
  const auto& box = decomp.local_box();
  for (int k = -1; k <= c.z; ++k)
    for (int j = -1; j <= c.y; ++j)
      for (int i = -1; i <= c.x; ++i) {
        const Vec3 x{(box.lo.x + i + 0.5) * dx, (box.lo.y + j + 0.5) * dx,
                     (box.lo.z + k + 0.5) * dx};
        const Vec3 v = u(x);
        for (int d = 0; d < 3; ++d) vel(i, j, k, d) = v[d];
      }
  for (int k = 0; k < n; ++k) {
    core::Rng r(4, decomp.rank() * n + k, 0, core::RngPurpose::kTest);
    Vec3 p;
    for (int d = 0; d < 3; ++d) {
      const double lo = std::max(pc.lo()[d], 0.5 * dx),
                   hi = std::min(pc.hi()[d], pc.domain_hi()[d] - 0.5 * dx);
      p[d] = r.uniform(lo, hi);
    }
    const Vec3 got = tc.interpolate(vel, tc.stencil(p)), want = u(p);
    for (int d = 0; d < 3; ++d) ASSERT_NEAR(got[d], want[d], 1e-12);
  }
  (void)vh;
}

INSTANTIATE_TEST_SUITE_P(Boundaries, Coupling,
                         ::testing::Values(std::array<bool, 3>{true, true, true},
                                           std::array<bool, 3>{false, false, false},
                                           std::array<bool, 3>{true, false, true}));
