/// \file test_sub_step_blocks.cpp
/// \brief The blocked sub-step (MechanicsParams::sub_step_block, seaweed_sub_step.cpp) changes no
/// bit: twelve grown plants tangled around one point, drawn together by a swirling inflow, with
/// joints weak enough to tear, give the same positions, orientations, velocities, contacts and
/// broken joints with the rank's spheres in one block as in blocks of 13 or 64 (odd sizes: blocks
/// that end inside a vector lane, and a plant spread over several blocks). On 2 and 3 ranks the
/// blocks also meet the rank boundary.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <vector>

#include "models/plants/seaweed_mechanics.hpp"
#include "models/plants/ulva_growth.hpp"

using namespace biota;
using namespace biota::models::plants;

namespace {

struct Outcome {
  std::vector<double> state;  // per sphere id: x, q, v, omega
  ClusterMetrics metrics;
};

Outcome run(std::int64_t block) {
  grid::Decomposition decomp(MPI_COMM_WORLD, {20, 20, 20}, {false, false, false});
  particles::ParticleComm comm(decomp, 0.01);
  MechanicsParams mp;
  mp.sub_step_block = block;
  mp.force_limit = 0.2;  // N: the inflow and the impacts tear about a fifth of the joints
  SeaweedBodies bodies(comm, mp);
  GrowthParams gp;
  gp.cycles = 2;
  gp.length_min = 0.01, gp.length_max = 0.02;
  gp.env_centre = {0.1, 0.1, 0.1};
  gp.env_radius = 0.05;
  gp.personal_radius = 0.005;
  std::vector<core::Vec3> seeds;
  for (int k = 0; k < 12; ++k) {
    const double a = 2 * M_PI * k / 12;
    seeds.push_back({0.1 + 0.012 * std::cos(a), 0.1 + 0.012 * std::sin(a), 0.1});
  }
  const Population pop = grow_population(gp, seeds);
  bodies.build(pop, static_cast<int>(seeds.size()));
  const long long n = bodies.global_count();
  for (int step = 0; step < 30; ++step) {
    bodies.begin_step();
    bodies.sample_fluid([](const core::Vec3& x) {  // a vortex drawing in toward its axis
      const double rx = x.x - 0.1, ry = x.y - 0.1;
      return core::Vec3{-2 * ry - 3 * rx, 2 * rx - 3 * ry, 0};
    });
    bodies.advance(1.0 / 60);
  }
  Outcome out;
  out.state.assign(static_cast<std::size_t>(13 * n), 0.0);
  const auto& s = bodies.set();
  for (std::size_t i = 0; i < s.n_owned(); ++i) {
    double* row = out.state.data() + 13 * s.id(i);
    for (int d = 0; d < 3; ++d) row[d] = s.pos(i)[d];
    for (int c = 0; c < 4; ++c) row[3 + c] = s.real(bodies.a_quat, c)[i];
    for (int d = 0; d < 3; ++d) row[7 + d] = s.real(bodies.a_vel, d)[i];
    for (int d = 0; d < 3; ++d) row[10 + d] = s.real(bodies.a_omega, d)[i];
  }
  MPI_Allreduce(MPI_IN_PLACE, out.state.data(), static_cast<int>(out.state.size()), MPI_DOUBLE,
                MPI_SUM, MPI_COMM_WORLD);
  out.metrics = bodies.clusters();
  return out;
}

}  // namespace

TEST(SubStepBlocks, ChangeNoBit) {
  const Outcome whole = run(0);
  // The case is one the blocks can get wrong: contacts between plants and torn joints.
  EXPECT_GT(whole.metrics.contacts, 0);
  EXPECT_GT(whole.metrics.broken_joints, 0);
  EXPECT_GT(whole.state.size(), 13u * 150);
  for (const std::int64_t block : {13, 64}) {
    const Outcome blocked = run(block);
    ASSERT_EQ(blocked.state.size(), whole.state.size());
    std::size_t differ = 0;
    for (std::size_t k = 0; k < whole.state.size(); ++k)
      differ += blocked.state[k] != whole.state[k] ? 1 : 0;  // bitwise: no tolerance
    EXPECT_EQ(differ, 0u) << "blocks of " << block;
    EXPECT_EQ(blocked.metrics.contacts, whole.metrics.contacts);
    EXPECT_EQ(blocked.metrics.broken_joints, whole.metrics.broken_joints);
    EXPECT_EQ(blocked.metrics.joints, whole.metrics.joints);
  }
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank == 0)
    std::printf("%zu spheres, %lld contacts, %lld broken joints, the same in blocks of 13 and 64\n",
                whole.state.size() / 13, whole.metrics.contacts, whole.metrics.broken_joints);
}
