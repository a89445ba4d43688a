/// \file test_skin_rebuild.cpp
/// \brief Neighbour-list skin check: two free spheres (no drag, neutrally buoyant) start 4 cm
/// apart, beyond the listed range (2 r + margin + skin = 2.1 cm), and fly at each other at
/// 0.5 m/s each (8.3 mm per physics step > skin/2). The list must be rebuilt inside the steps, the
/// contact must be found (they bounce off with the contact spring) and not missed (they would pass
/// through each other). On 2 ranks they cross the rank boundary at x = 0.1 m.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>

#include "models/plants/seaweed_mechanics.hpp"

using namespace biota;
using namespace biota::models::plants;

TEST(SkinRebuild, FastApproachIsNotMissed) {
  grid::Decomposition decomp(MPI_COMM_WORLD, {20, 20, 20}, {false, false, false});
  particles::ParticleComm comm(decomp, 0.01);
  MechanicsParams mp;
  mp.drag_cd = 0;
  mp.plant_density = mp.water_density;  // no net weight
  SeaweedBodies bodies(comm, mp);
  Population pop;
  pop.buds.push_back({0, ~GlobalId{0}, 0, 0, 0, {0.08, 0.1, 0.1}});
  pop.buds.push_back({1, ~GlobalId{0}, 1, 0, 0, {0.12, 0.1, 0.1}});
  bodies.build(pop, 2);
  auto& s = bodies.set();
  for (std::size_t i = 0; i < s.n_owned(); ++i)
    s.set_vec3(bodies.a_vel, i, {s.id(i) == 0 ? 0.5 : -0.5, 0, 0});
  double min_gap = 1e9, last = 0;
  const long long rebuilds0 = bodies.rebuilds();
  for (int step = 0; step < 8; ++step) {
    bodies.begin_step();
    bodies.sample_fluid([](const core::Vec3&) { return core::Vec3{}; });
    bodies.advance(1.0 / 60);
    double x[2] = {0, 0};
    for (std::size_t i = 0; i < s.n_owned(); ++i) x[s.id(i)] = s.pos(i).x;
    MPI_Allreduce(MPI_IN_PLACE, x, 2, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    last = x[1] - x[0];
    min_gap = std::min(min_gap, last);
  }
  long long rebuilds = bodies.rebuilds() - rebuilds0;
  MPI_Allreduce(MPI_IN_PLACE, &rebuilds, 1, MPI_LONG_LONG, MPI_MAX, MPI_COMM_WORLD);
  // Contact spring 50 N/m, m = 0.63 g, relative speed 1 m/s: overlap ~ v sqrt(m_red / k) = 2.5 mm.
  EXPECT_GT(min_gap, 0.005);
  EXPECT_LT(min_gap, 0.01);  // they did touch
  EXPECT_GT(last, 0.02);     // and bounced apart again
  EXPECT_GE(rebuilds, 3);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank == 0)
    std::printf("closest centre distance %.4f m, final %.4f m, %lld list rebuilds\n", min_gap, last,
                rebuilds);
}

/// The inner contact list (MechanicsParams::inner_skin) only skips pairs that cannot touch: a
/// head-on approach at 0.5 m/s (0.42 mm per sub-step, so the 2-mm inner list is re-filtered every
/// few sub-steps) gives bit for bit the trajectory of walking the whole neighbour list.
TEST(SkinRebuild, InnerListChangesNothing) {
  grid::Decomposition decomp(MPI_COMM_WORLD, {20, 20, 20}, {false, false, false});
  auto run = [&](double inner_skin, long long* filters) {
    particles::ParticleComm comm(decomp, 0.01);
    MechanicsParams mp;
    mp.drag_cd = 0;
    mp.plant_density = mp.water_density;
    mp.inner_skin = inner_skin;
    SeaweedBodies bodies(comm, mp);
    Population pop;
    // Two short chains aimed at each other, so joints and contacts are both in the lists.
    pop.buds.push_back({0, ~GlobalId{0}, 0, 0, 0, {0.06, 0.1, 0.1}});
    pop.buds.push_back({1, 0, 0, 0, 0, {0.08, 0.1, 0.1}});
    pop.buds.push_back({2, ~GlobalId{0}, 1, 0, 0, {0.14, 0.104, 0.1}});
    pop.buds.push_back({3, 2, 1, 0, 0, {0.12, 0.104, 0.1}});
    bodies.build(pop, 2);
    auto& s = bodies.set();
    for (std::size_t i = 0; i < s.n_owned(); ++i)
      s.set_vec3(bodies.a_vel, i, {s.u64(bodies.u_plant)[i] == 0 ? 0.5 : -0.5, 0, 0});
    for (int step = 0; step < 8; ++step) {
      bodies.begin_step();
      bodies.sample_fluid([](const core::Vec3&) { return core::Vec3{}; });
      bodies.advance(1.0 / 60);
    }
    std::vector<double> x(3 * 6, 0.0);
    for (std::size_t i = 0; i < s.n_owned(); ++i)
      for (int d = 0; d < 3; ++d) x[3 * s.id(i) + d] = s.pos(i)[d];
    MPI_Allreduce(MPI_IN_PLACE, x.data(), static_cast<int>(x.size()), MPI_DOUBLE, MPI_SUM,
                  MPI_COMM_WORLD);
    *filters = bodies.filters();
    return x;
  };
  long long f_all = 0, f_inner = 0;
  const auto all = run(0.0, &f_all), inner = run(0.002, &f_inner);
  for (std::size_t k = 0; k < all.size(); ++k) EXPECT_EQ(all[k], inner[k]) << "value " << k;
  EXPECT_LT(f_inner, f_all);  // the inner list was reused between filters
}
