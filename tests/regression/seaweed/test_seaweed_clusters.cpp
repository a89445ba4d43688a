// Reduced-size reproduction of the paper's finding with a prescribed recirculating flow (a
// fountain cell: up in the middle, down at the sides): the time-averaged largest-cluster share
// grows strictly from growth cycle 1 to 3 to 5, cycle 1 shows (almost) no clustering and at cycle 5
// a majority of the plants form one cluster.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <numbers>

#include "models/plants/seaweed_mechanics.hpp"
#include "models/plants/ulva_growth.hpp"

using namespace biota;
using namespace biota::models::plants;

namespace {

struct Result {
  double mean_share = 0;
  long long spheres = 0;
  ClusterMetrics first, last;
};

Result run(int cycles, int plants, double seconds) {
  const double L = 0.5, dx = 0.01;  // 50 cells of 1 cm
  grid::Decomposition decomp(MPI_COMM_WORLD, {50, 50, 50}, {false, false, false});
  particles::ParticleComm comm(decomp, dx);
  GrowthParams gp;
  gp.cycles = cycles;
  gp.env_centre = {L / 2, L / 2, L / 2};
  gp.env_radius = 0.2;
  auto seeds = place_seeds(7, plants, {0.08, 0.08, 0.1}, {0.42, 0.42, 0.4}, 0.12);
  auto pop = grow_population(gp, seeds);
  MechanicsParams mp;
  SeaweedBodies bodies(comm, mp);
  bodies.build(pop, plants);
  const double U = 0.05;  // m/s
  auto flow = [&](const core::Vec3& x) {
    const double a = std::numbers::pi * x.x / L, c = std::numbers::pi * x.z / L;
    return core::Vec3{-U * std::cos(a) * std::sin(c), 0.0, U * std::sin(a) * std::cos(c)};
  };
  Result r;
  r.spheres = bodies.global_count();
  const double dt = 1.0 / 60;
  const int steps = static_cast<int>(std::lround(seconds / dt));
  int samples = 0;
  for (int s = 0; s <= steps; ++s) {
    bodies.begin_step();
    if (s % 6 == 0) {
      auto cm = bodies.clusters();
      if (s == 0) r.first = cm;
      r.last = cm;
      r.mean_share += cm.largest_share;
      ++samples;
    }
    if (s == steps) break;
    bodies.sample_fluid(flow);
    bodies.advance(dt);
  }
  r.mean_share /= samples;
  EXPECT_EQ(bodies.global_count(), r.spheres);
  return r;
}

}  // namespace

TEST(SeaweedClusters, LargestClusterShareGrowsWithGrowthStage) {
  const int plants = 30;
  const double seconds = 1.0;
  double share[6] = {};
  for (int c : {1, 3, 5}) {
    auto r = run(c, plants, seconds);
    share[c] = r.mean_share;
    std::printf(
        "cycle %d: spheres %lld, mean largest share %.3f (t0 %.3f, end %.3f), clusters %d->%d, "
        "contacts %lld->%lld, broken %lld\n",
        c, r.spheres, r.mean_share, r.first.largest_share, r.last.largest_share, r.first.clusters,
        r.last.clusters, r.first.contacts, r.last.contacts, r.last.broken_joints);
  }
  EXPECT_LT(share[1], share[3]);
  EXPECT_LT(share[3], share[5]);
  EXPECT_LE(share[1], 0.1);  // "near zero": at most 3 of 30 plants in the largest cluster
  EXPECT_GT(share[5], 0.5);
}
