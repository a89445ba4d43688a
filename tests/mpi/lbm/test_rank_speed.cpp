// measure_rank_speeds: one speed per rank, the same vector on every rank, the fastest 1. (Which
// rank is slower is a timing, not asserted here: the development VM's cores differ by up to 1.7x
// from minute to minute on their own. grid's WeightedBlockStarts tests check the cut.)
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>

#include "solvers/lbm/rank_speed.hpp"

using namespace biota;

namespace {
solvers::lbm::LbmParams small_tank() {
  solvers::lbm::LbmParams p;
  p.lattice = "D3Q15";
  p.cells = {48, 48, 24};
  p.viscosity = 1e-3 * p.dx * p.dx / p.dt;
  return p;
}
}  // namespace

TEST(RankSpeed, OneVectorOnEveryRankFastestIsOne) {
  int size = 0;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const auto speed = solvers::lbm::measure_rank_speeds(MPI_COMM_WORLD, small_tank());
  ASSERT_EQ(static_cast<int>(speed.size()), size);
  EXPECT_EQ(*std::max_element(speed.begin(), speed.end()), 1.0);
  for (double s : speed) EXPECT_TRUE(s > 0 && s <= 1) << s;
  std::vector<double> root = speed;
  MPI_Bcast(root.data(), size, MPI_DOUBLE, 0, MPI_COMM_WORLD);
  EXPECT_EQ(root, speed);
}
