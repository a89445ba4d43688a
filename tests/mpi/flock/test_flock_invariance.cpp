// Flock scenario: the same run on 1 rank (a sub-communicator of rank 0) and on all ranks gives
// bitwise the same boids and the same sandpile; restart (N steps, checkpoint, restart on the other
// rank count, N steps) equals 2N steps straight. Run at np = 1, 2, 3.
#include <gtest/gtest.h>
#include <mpi.h>

#include <filesystem>
#include <string>

#include "core/config.hpp"
#include "core/timers.hpp"
#include "scenarios/flock_scenario.hpp"

using namespace biota;

namespace {

core::ConfigSchema schema() {
  core::ConfigSchema s;
  s.add_string("scenario", std::nullopt, {}, "scenario");
  s.add_int("seed", 12345, 0, std::nullopt, "seed");
  scenarios::FlockScenario::declare_config(s);
  return s;
}

// Small but complete: take-off, flocking, a predator attacking from step 10 with soft walls,
// avalanches (warm sandpile), all noise on. 216 prey on a 6^3 lattice.
const char* kDeck = R"(
scenario = "flock"
seed = 7
[flock]
dt = 0.05
stats_interval = 1000
[flock.domain]
size = [24.0, 24.0, 24.0]
dx = 4.0
boundary = "walls"
wall_margin = 4.0
[flock.boids]
perception_radius = 3.0
[flock.predator]
start_time = 0.5
start = [12.0, 12.0, 14.0]
[flock.sandpile]
size = 6
warmup = 3000
trigger_radius = 30.0
grains_per_frame = 3
[flock.noise]
levels = 4
[flock.takeoff]
ifs = "gasket"
origin = [6.0, 6.0, 9.0]
scale = 12.0
interval = 0.002
)";

std::vector<scenarios::BoidRecord> run(MPI_Comm comm, const core::Config& cfg, int steps,
                                       const std::string& dir, const std::string& restart_from,
                                       const std::string& checkpoint_to, std::int64_t* topplings) {
  core::Timers timers;
  scenarios::RunContext ctx{comm, cfg, timers, dir};
  scenarios::FlockScenario sc(ctx);
  if (!restart_from.empty()) sc.read_checkpoint(restart_from);
  for (int k = 0; k < steps; ++k) sc.step();
  if (!checkpoint_to.empty()) sc.write_checkpoint(checkpoint_to);
  if (topplings) *topplings = sc.sandpile().topplings();
  return sc.gather_boids();
}

void expect_same(const std::vector<scenarios::BoidRecord>& a,
                 const std::vector<scenarios::BoidRecord>& b) {
  ASSERT_EQ(a.size(), b.size());
  std::size_t diff = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].id, b[i].id);
    if (!(a[i].x == b[i].x) || !(a[i].v == b[i].v)) ++diff;
  }
  EXPECT_EQ(diff, 0u) << "boids differing (bitwise)";
}

}  // namespace

class FlockInvariance : public ::testing::TestWithParam<const char*> {};

TEST_P(FlockInvariance, SameBoidsOnAnyRankCountAndAcrossRestart) {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const auto sch = schema();
  const std::string boundary = GetParam();
  const auto cfg = core::Config::from_string(sch, kDeck, "flock_invariance.toml",
                                             {"flock.domain.boundary=\"" + boundary + "\""});
  const std::string dir = "flock_invariance_" + boundary + "_np" + std::to_string(size);
  if (rank == 0) std::filesystem::create_directories(dir);
  MPI_Barrier(MPI_COMM_WORLD);
  constexpr int N = 60;
  MPI_Comm solo;
  MPI_Comm_split(MPI_COMM_WORLD, rank == 0 ? 0 : MPI_UNDEFINED, 0, &solo);

  // Reference: 2N steps on one rank (rank 0 alone), broadcast.
  std::vector<scenarios::BoidRecord> ref;
  std::int64_t ref_topplings = 0;
  if (rank == 0)
    ref = run(solo, cfg, 2 * N, dir + "/serial", "", dir + "/serial_N.h5", &ref_topplings);
  std::size_t n = ref.size();
  MPI_Bcast(&n, sizeof n, MPI_BYTE, 0, MPI_COMM_WORLD);
  ref.resize(n);
  MPI_Bcast(ref.data(), static_cast<int>(n * sizeof(scenarios::BoidRecord)), MPI_BYTE, 0,
            MPI_COMM_WORLD);
  MPI_Bcast(&ref_topplings, 1, MPI_INT64_T, 0, MPI_COMM_WORLD);
  EXPECT_EQ(n, 217u);  // 216 prey + 1 predator
  EXPECT_GT(ref_topplings, 0);

  // 2N steps on all ranks.
  std::int64_t topplings = 0;
  auto all = run(MPI_COMM_WORLD, cfg, 2 * N, dir + "/all", "", "", &topplings);
  expect_same(ref, all);
  EXPECT_EQ(topplings, ref_topplings);

  // N steps on all ranks, checkpoint; restart on one rank for N more; and the other way round.
  run(MPI_COMM_WORLD, cfg, N, dir + "/a", "", dir + "/all_N.h5", nullptr);
  std::vector<scenarios::BoidRecord> r1;
  if (rank == 0) r1 = run(solo, cfg, N, dir + "/b", dir + "/all_N.h5", "", &topplings);
  if (rank == 0) {
    expect_same(ref, r1);
    EXPECT_EQ(topplings, ref_topplings);
  }
  if (rank == 0) run(solo, cfg, N, dir + "/c", "", dir + "/serial_half.h5", nullptr);
  MPI_Barrier(MPI_COMM_WORLD);
  auto r2 = run(MPI_COMM_WORLD, cfg, N, dir + "/d", dir + "/serial_half.h5", "", &topplings);
  expect_same(ref, r2);
  EXPECT_EQ(topplings, ref_topplings);
  if (solo != MPI_COMM_NULL) MPI_Comm_free(&solo);
}

INSTANTIATE_TEST_SUITE_P(Boundaries, FlockInvariance, ::testing::Values("walls", "periodic"));
