// The population grown on every rank is bit-identical on every rank and therefore on every rank
// count: growth is replicated, with streams keyed by growth-unit id and cycle, never by rank.
// (A golden hash across machines is not used: glibc picks sin/cos code paths per CPU.)
#include <gtest/gtest.h>
#include <mpi.h>

#include <bit>
#include <cstdint>

#include "models/plants/ulva_growth.hpp"

using namespace biota::models::plants;

TEST(GrowthInvariance, SamePlantsOnEveryRankAndRankCount) {
  GrowthParams gp;
  gp.env_centre = {0.25, 0.25, 0};
  std::vector<biota::core::Vec3> seeds;
  for (int i = 0; i < 50; ++i) seeds.push_back({0.07 * (i % 7), 0.07 * (i / 7), 0.01 * (i % 3)});
  auto pop = grow_population(gp, seeds);
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&](std::uint64_t v) { h = (h ^ v) * 1099511628211ull; };
  for (const auto& b : pop.buds) {
    mix(b.id), mix(b.parent), mix(b.plant), mix(b.cycle);
    for (int d = 0; d < 3; ++d) mix(std::bit_cast<std::uint64_t>(b.pos[d]));
  }
  std::uint64_t hmin = h, hmax = h;
  MPI_Allreduce(MPI_IN_PLACE, &hmin, 1, MPI_UINT64_T, MPI_MIN, MPI_COMM_WORLD);
  MPI_Allreduce(MPI_IN_PLACE, &hmax, 1, MPI_UINT64_T, MPI_MAX, MPI_COMM_WORLD);
  EXPECT_EQ(hmin, hmax);
  std::printf("buds %zu hash %llu\n", pop.buds.size(), static_cast<unsigned long long>(h));
  EXPECT_GT(pop.buds.size(), 50u * 10);
}
