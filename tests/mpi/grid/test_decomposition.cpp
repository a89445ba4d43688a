#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <limits>
#include <vector>

#include "grid/decomposition.hpp"
#include "grid/plane_weights.hpp"
#include "grid/two_phase_cut.hpp"

using namespace biota::grid;

TEST(BlockStart, UnevenSplitGivesLargerBlocksFirst) {
  EXPECT_EQ(block_start(100, 3, 0), 0);
  EXPECT_EQ(block_start(100, 3, 1), 34);
  EXPECT_EQ(block_start(100, 3, 2), 67);
  EXPECT_EQ(block_start(100, 3, 3), 100);
  EXPECT_EQ(block_start(7, 7, 7), 7);
}

TEST(Decomposition, BoxesTileTheDomainExactlyOnce) {
  for (Index3 n : {Index3{100, 7, 5}, Index3{3, 4, 5}, Index3{17, 17, 17}}) {
    Decomposition d(MPI_COMM_WORLD, n, {false, true, false});
    long long local = d.local_cells().product(), total = 0;
    MPI_Allreduce(&local, &total, 1, MPI_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
    EXPECT_EQ(total, n.product());
    // Every cell of my box is owned by me; owner_of_cell agrees with box_of for all cells.
    for (int k = 0; k < n.z; ++k)
      for (int j = 0; j < n.y; ++j)
        for (int i = 0; i < n.x; ++i) {
          const bool mine = d.local_box().contains({i, j, k});
          ASSERT_EQ(d.owner_of_cell({i, j, k}) == d.rank(), mine) << i << " " << j << " " << k;
        }
    // Periodic wrap on y: the owner of y = -1 is the owner of y = ny - 1.
    EXPECT_EQ(d.owner_of_cell({0, -1, 0}), d.owner_of_cell({0, n.y - 1, 0}));
    EXPECT_EQ(d.owner_of_point({0.5, n.y + 0.25, 0.5}), d.owner_of_cell({0, 0, 0}));
  }
}

TEST(WeightedBlockStarts, EqualSumsAndMinimumThickness) {
  // Uniform weight: the even split's sizes (cut at the first plane reaching the share).
  EXPECT_EQ(weighted_block_starts(std::vector<double>(10, 1.0), 2, 1),
            (std::vector<int>{0, 5, 10}));
  // All the weight in planes 0-1 of 10: cut after them, 2 planes vs 8.
  std::vector<double> w(10, 0.0);
  w[0] = w[1] = 1;
  EXPECT_EQ(weighted_block_starts(w, 2, 1), (std::vector<int>{0, 1, 10}));
  // ... unless blocks must be 3 planes thick.
  EXPECT_EQ(weighted_block_starts(w, 2, 3), (std::vector<int>{0, 3, 10}));
  // Three parts, each block at least one plane even when one plane holds everything.
  std::vector<double> spike(9, 0.0);
  spike[8] = 1;
  EXPECT_EQ(weighted_block_starts(spike, 3, 1), (std::vector<int>{0, 7, 8, 9}));
}

TEST(PlaneWeights, PointsOutsideOrNotFiniteCountForAnEndPlane) {
  PlaneWeights w({1, 2, 1}, {4, 5, 6}, 0.5);
  const double inf = std::numeric_limits<double>::infinity();
  w.add({0, -3.0, 0});                                           // below: plane 0
  w.add({0, 1.2, 0}, 2.0);                                       // plane 2
  w.add({0, inf, 0});                                            // above: the last plane
  w.add({0, std::numeric_limits<double>::quiet_NaN(), 0}, 4.0);  // NaN: plane 0
  EXPECT_TRUE(w.planes()[0].empty());
  EXPECT_EQ(w.planes()[1], (std::vector<double>{5, 0, 2, 0, 1}));
  EXPECT_TRUE(w.planes()[2].empty());
}

TEST(WeightedBlockStarts, CapacitiesSplitTheWeightInProportion) {
  const std::vector<double> uniform(100, 1.0);
  // Equal capacities: the bits of the equal-parts overload.
  EXPECT_EQ(weighted_block_starts(uniform, {0.5, 0.5, 0.5}, 1),
            weighted_block_starts(uniform, 3, 1));
  // A core at half the speed of the other gets a third of the planes.
  EXPECT_EQ(weighted_block_starts(uniform, {1.0, 0.5}, 1), (std::vector<int>{0, 67, 100}));
  EXPECT_EQ(weighted_block_starts(uniform, {0.5, 1.0}, 1), (std::vector<int>{0, 34, 100}));
  // ... but never below the minimum thickness.
  EXPECT_EQ(weighted_block_starts(uniform, {1.0, 0.01}, 25), (std::vector<int>{0, 75, 100}));
}

TEST(BlockCapacities, SlowestRankOfASlabSetsItsPace) {
  // 2 x 3 x 1 rank grid, row-major ranks: rank r has coords (r / 3, r % 3, 0).
  const std::vector<double> speed{1.0, 0.5, 1.0, 0.9, 1.0, 0.7};
  const auto cap = block_capacities({2, 3, 1}, speed);
  EXPECT_EQ(cap[0], (std::vector<double>{0.5, 0.7}));
  EXPECT_EQ(cap[1], (std::vector<double>{0.9, 0.5, 0.7}));
  EXPECT_TRUE(cap[2].empty());
  // The layout assumed above is the one Decomposition gets from MPI_Cart_create.
  Decomposition d(MPI_COMM_WORLD, {12, 12, 12}, {false, false, false});
  const Index3 n = d.dims();
  const Index3 c = d.coords();
  EXPECT_EQ(d.rank(), (c.x * n.y + c.y) * n.z + c.z);
}

TEST(Decomposition, GivenBlockStartsTileTheDomainAndMatchOwners) {
  const Index3 n{11, 40, 6};
  Decomposition even(MPI_COMM_WORLD, n, {false, false, false});
  std::array<std::vector<int>, 3> starts;
  for (int a = 0; a < 3; ++a) {
    if (even.dims()[a] == 1) continue;
    std::vector<double> w(n[a], 1.0);
    for (int k = 0; k < n[a] / 4; ++k) w[k] = 10;  // heavy low quarter: thinner low blocks
    starts[a] = weighted_block_starts(w, even.dims()[a], 2);
  }
  Decomposition d(MPI_COMM_WORLD, n, {false, false, false}, {0, 0, 0}, {}, starts);
  long long local = d.local_cells().product(), total = 0;
  MPI_Allreduce(&local, &total, 1, MPI_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_EQ(total, n.product());
  for (int k = 0; k < n.z; ++k)
    for (int j = 0; j < n.y; ++j)
      for (int i = 0; i < n.x; ++i)
        ASSERT_EQ(d.owner_of_cell({i, j, k}) == d.rank(), d.local_box().contains({i, j, k}));
  for (int a = 0; a < 3; ++a) {
    if (d.dims()[a] == 1) continue;
    EXPECT_LT(d.block_start_of(a, 1), block_start(n[a], d.dims()[a], 1)) << "axis " << a;
    EXPECT_GE(d.thinnest(a), 2);
    // The thinnest and widest blocks against the block starts (uneven here: the heavy quarter).
    int thin = n[a], wide = 0;
    for (int i = 0; i < d.dims()[a]; ++i) {
      const int cells = d.block_start_of(a, i + 1) - d.block_start_of(a, i);
      thin = std::min(thin, cells), wide = std::max(wide, cells);
    }
    EXPECT_EQ(d.thinnest(a), thin);
    EXPECT_EQ(d.widest(a), wide);
    EXPECT_GT(wide, thin);
    for (int i = 0; i < d.dims()[a]; ++i) EXPECT_EQ(d.block_of(a, d.block_start_of(a, i)), i);
  }
}

TEST(Decomposition, NeighboursAreMutual) {
  Decomposition d(MPI_COMM_WORLD, {30, 20, 10}, {true, false, true});
  for (int a = 0; a < 3; ++a) {
    // Send my rank to the high neighbour; what I receive from the low one must be its rank.
    int mine = d.rank(), from_low = -2;
    MPI_Sendrecv(&mine, 1, MPI_INT, d.neighbor(a, 1), 0, &from_low, 1, MPI_INT, d.neighbor(a, 0), 0,
                 d.comm(), MPI_STATUS_IGNORE);
    if (d.neighbor(a, 0) != MPI_PROC_NULL) {
      EXPECT_EQ(from_low, d.neighbor(a, 0));
    }
    if (!d.periodic(a) && d.coords()[a] == 0) {
      EXPECT_EQ(d.neighbor(a, 0), MPI_PROC_NULL);
    }
  }
}

TEST(Decomposition, ForcedDimsAreHonoured) {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  Decomposition d(MPI_COMM_WORLD, {4, 4, 90}, {false, false, false}, {1, 1, 0});
  EXPECT_EQ(d.dims().x, 1);
  EXPECT_EQ(d.dims().y, 1);
  EXPECT_EQ(d.dims().z, size);
}

// Free axes get MPI_Dims_create's counts at the fewest cut faces; ties keep the fewest ranks on z
// (the vertical), then on x (the unit stride): a cube on 2 or 3 ranks is cut across y.
TEST(Decomposition, FewestCutFacesTiesAvoidZThenX) {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  Decomposition cube(MPI_COMM_WORLD, {24, 24, 24}, {false, false, false});
  EXPECT_EQ(cube.dims().y, size);  // 1, 2 or 3 ranks: all on y
  // A long box keeps its cut across the long axis (fewer cut faces than a y cut).
  Decomposition slab(MPI_COMM_WORLD, {80, 40, 40}, {false, false, false});
  EXPECT_EQ(slab.dims().x, size);
  // A tall box is cut across z: fewer cut faces wins over the tie rule.
  Decomposition tall(MPI_COMM_WORLD, {20, 20, 90}, {false, false, false});
  EXPECT_EQ(tall.dims().z, size);
  // Given dims stay; only the free axes are permuted.
  Decomposition given(MPI_COMM_WORLD, {24, 24, 24}, {false, false, false}, {size, 0, 0});
  EXPECT_EQ(given.dims().x, size);
  // 2D (one cell along z): the cut goes across y (whole rows) rather than x.
  Decomposition flat(MPI_COMM_WORLD, {64, 64, 1}, {false, false, true});
  EXPECT_EQ(flat.dims().y, size);
}

TEST(TwoPhaseCut, CostIsTheSlowestRanksCellsPlusItems) {
  const Index3 dims{1, 2, 1}, cells{1, 10, 1};
  const std::array<std::vector<int>, 3> starts{{{}, {0, 4, 10}, {}}};
  const std::array<std::vector<double>, 3> items{{{}, std::vector<double>(10, 1.0), {}}};
  // Rank 1 has 6 of 10 cells and 6 of 10 items: 6 + 2 x 6.
  EXPECT_DOUBLE_EQ(two_phase_cost(dims, cells, starts, items, 2.0, {}), 18.0);
  // Rank 1 at half speed: 12 + 2 x 12.
  EXPECT_DOUBLE_EQ(two_phase_cost(dims, cells, starts, items, 2.0, {1.0, 0.5}), 36.0);
}

TEST(TwoPhaseCut, PicksTheCutOfLeastMaxPlusMax) {
  const Index3 dims{1, 2, 1}, cells{1, 100, 1};
  // 600 items, 10 in each of the planes 0-59: equal items at y = 30, equal cells at 50.
  std::array<std::vector<double>, 3> items{{{}, std::vector<double>(100, 0.0), {}}};
  for (int p = 0; p < 60; ++p) items[1][p] = 10;
  // Items nearly free: equal cells.
  EXPECT_EQ(two_phase_block_starts(dims, cells, items, 1e-3, {}, 1)[1],
            (std::vector<int>{0, 50, 100}));
  // Items dear: equal items (a plane of cells costs less than the items it moves).
  EXPECT_EQ(two_phase_block_starts(dims, cells, items, 1e3, {}, 1)[1],
            (std::vector<int>{0, 30, 100}));
  // The cut balancing the sum cells + item_cost x items leaves both phases waiting on a rank;
  // the chosen cut beats it, and is no worse than equal cells. With items at 0.05 (a plane of
  // cells costs more than the half an item's cost it moves) equal cells (cost 50 + 0.05 x 500)
  // beats the sum's cut at 44 (56 + 0.05 x 440); with items at 5 the exact equal-items cut
  // (70 + 5 x 300) beats the sum's cut at 31 (69 + 5 x 310).
  for (const double item_cost : {0.05, 5.0}) {
    std::array<std::vector<double>, 3> sum_weight{{{}, std::vector<double>(100, 1.0), {}}};
    for (int p = 0; p < 100; ++p) sum_weight[1][p] += item_cost * items[1][p];
    const auto summed = balanced_block_starts(dims, cells, sum_weight, {}, 1);
    const auto equal = balanced_block_starts(dims, cells, {}, {}, 1);
    const auto chosen = two_phase_block_starts(dims, cells, items, item_cost, {}, 1);
    const double c_chosen = two_phase_cost(dims, cells, chosen, items, item_cost, {});
    EXPECT_LT(c_chosen, two_phase_cost(dims, cells, summed, items, item_cost, {})) << item_cost;
    EXPECT_LE(c_chosen, two_phase_cost(dims, cells, equal, items, item_cost, {})) << item_cost;
    EXPECT_EQ(chosen[1], (std::vector<int>{0, item_cost < 1 ? 50 : 30, 100})) << item_cost;
  }
}
