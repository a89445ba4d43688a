// particles::rebalance_starts: the cut moves in proportion to the ranks' measured speeds, and not
// at all when they are balanced within the tolerance. Run at np = 1, 2, 3.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "particles/load_balance.hpp"

using namespace biota;

namespace {

struct Points {
  std::vector<double> c[3];
  const double* x[3] = {nullptr, nullptr, nullptr};
};

// One particle at the centre of every cell of this rank's block (dx = 1).
Points one_per_cell(const grid::Decomposition& d) {
  Points p;
  const grid::Box b = d.local_box();
  for (int k = b.lo.z; k < b.hi.z; ++k)
    for (int j = b.lo.y; j < b.hi.y; ++j)
      for (int i = b.lo.x; i < b.hi.x; ++i) {
        p.c[0].push_back(i + 0.5), p.c[1].push_back(j + 0.5), p.c[2].push_back(k + 0.5);
      }
  for (int a = 0; a < 3; ++a) p.x[a] = p.c[a].data();
  return p;
}

}  // namespace

TEST(LoadBalance, BlocksFollowTheMeasuredSpeed) {
  const core::Index3 cells{12, 60, 12};
  grid::Decomposition d(MPI_COMM_WORLD, cells, {true, true, true}, {1, 0, 1});
  const int P = d.size(), r = d.rank();
  const Points p = one_per_cell(d);
  const std::size_t n = p.c[0].size();
  // Rank r is (r + 1) times slower per particle: it should get a share 1/(r + 1) of the speed sum.
  const double seconds = (r + 1) * 1e-6 * static_cast<double>(n);
  const auto moved = particles::rebalance_starts(d, p.x, nullptr, n, 1.0, {}, seconds,
                                                 static_cast<double>(n), 0.05, 2);
  if (P == 1) {
    EXPECT_FALSE(moved.moves());
    return;
  }
  ASSERT_TRUE(moved.moves());
  EXPECT_NEAR(moved.imbalance, P / ((P + 1) / 2.0), 1e-12);  // slowest / mean of 1..P
  const std::vector<int>& s = moved.starts[1];
  ASSERT_EQ(s.size(), static_cast<std::size_t>(P + 1));
  double speed_sum = 0;
  for (int q = 0; q < P; ++q) speed_sum += 1.0 / (q + 1);
  for (int q = 0; q < P; ++q) {
    const double share = cells.y * (1.0 / (q + 1)) / speed_sum;
    EXPECT_LE(std::abs((s[q + 1] - s[q]) - share), 1.0) << "block " << q;
    EXPECT_GE(s[q + 1] - s[q], 2) << "thinner than min_cells";
  }
  EXPECT_TRUE(moved.starts[0].empty() && moved.starts[2].empty());  // axes not split

  // Per-particle costs weigh the planes: the particles of the low half cost 3 each, so with
  // equal speeds the low half gets thinner blocks than the high half.
  std::vector<float> cost(n);
  for (std::size_t i = 0; i < n; ++i) cost[i] = p.c[1][i] < cells.y / 2 ? 3.0f : 1.0f;
  double units = 0;
  for (float c : cost) units += c;
  const auto weighted =
      particles::rebalance_starts(d, p.x, cost.data(), n, 1.0, {}, units * 1e-6, units, 0.0, 2);
  if (weighted.moves()) {  // even blocks carry unequal work, so they move
    const std::vector<int>& w = weighted.starts[1];
    EXPECT_LT(w[1] - w[0], w[P] - w[P - 1]);
  } else {
    ADD_FAILURE() << "unequal work per block did not move the cut";
  }
}

// One plane 20 times heavier than the others: cutting where the running weight first reaches a
// share puts it in the block before the cut; the refinement finds the cut of the least
// slowest block (checked against every possible cut on 2 and 3 ranks, equal speeds).
TEST(LoadBalance, AHeavyPlaneGoesWhereItCostsLeast) {
  const core::Index3 cells{12, 60, 12};
  grid::Decomposition d(MPI_COMM_WORLD, cells, {false, false, false}, {1, 0, 1});
  const int P = d.size();
  if (P == 1 || P > 3) GTEST_SKIP() << "2 or 3 ranks";
  const Points p = one_per_cell(d);
  const std::size_t n = p.c[0].size();
  constexpr int kHeavy = 31;  // on 2 ranks: lower_bound cuts at 32, the best cut is 31
  std::vector<float> cost(n);
  double units = 0;
  for (std::size_t i = 0; i < n; ++i) units += cost[i] = p.c[1][i] == kHeavy + 0.5 ? 20.0f : 1.0f;
  const auto decision =
      particles::rebalance_starts(d, p.x, cost.data(), n, 1.0, {}, units * 1e-6, units, 0.0, 1);
  std::vector<int> s(P + 1);  // the cut after the decision (kept when it is already the best)
  for (int b = 0; b <= P; ++b)
    s[b] = decision.moves() ? decision.starts[1][b] : d.block_start_of(1, b);
  if (P == 2) {
    EXPECT_TRUE(decision.moves() && s[1] == kHeavy);
  }
  std::vector<double> plane(cells.y, cells.x * cells.z * 1.0);
  plane[kHeavy] *= 20;
  const auto block = [&](int lo, int hi) {
    double w = 0;
    for (int k = lo; k < hi; ++k) w += plane[k];
    return w;
  };
  double got = 0;
  for (int b = 0; b < P; ++b) got = std::max(got, block(s[b], s[b + 1]));
  double best = 1e300;
  for (int c1 = 1; c1 < cells.y; ++c1)
    if (P == 2)
      best = std::min(best, std::max(block(0, c1), block(c1, cells.y)));
    else
      for (int c2 = c1 + 1; c2 < cells.y; ++c2)
        best = std::min(best, std::max({block(0, c1), block(c1, c2), block(c2, cells.y)}));
  EXPECT_EQ(got, best);
}

TEST(LoadBalance, NoMoveWithinTheTolerance) {
  grid::Decomposition d(MPI_COMM_WORLD, {8, 30, 8}, {false, false, false}, {1, 0, 1});
  const Points p = one_per_cell(d);
  const std::size_t n = p.c[0].size();
  // 4% slower on the last rank: within a 5% tolerance of the mean.
  const double seconds = (d.rank() == d.size() - 1 ? 1.04 : 1.0) * static_cast<double>(n);
  const auto decision = particles::rebalance_starts(d, p.x, nullptr, n, 1.0, {}, seconds,
                                                    static_cast<double>(n), 0.05, 1);
  EXPECT_FALSE(decision.moves());
  // No work measured on some rank (a fresh start): keep the cut, whatever the tolerance.
  const auto none = particles::rebalance_starts(d, p.x, nullptr, n, 1.0, {},
                                                d.rank() == 0 ? 0.0 : 1.0, 1.0, 0.0, 1);
  EXPECT_FALSE(none.moves());
  EXPECT_EQ(none.imbalance, 0.0);
}
