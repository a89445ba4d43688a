// Flock scenario: the same run on 1 rank (a sub-communicator of rank 0) and on all ranks gives
// bitwise the same boids and the same sandpile; restart (N steps, checkpoint, restart on the other
// rank count, N steps) equals 2N steps straight. Run at np = 1, 2, 3.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "core/config.hpp"
#include "core/timers.hpp"
#include "scenarios/flock_scenario.hpp"

using namespace biota;

namespace {

core::ConfigSchema schema() {
  core::ConfigSchema s;
  s.add_string("scenario", std::nullopt, {}, "scenario");
  s.add_int("seed", 12345, 0, 1'000'000'000'000'000'000, "seed");
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

// The load balance moves the cut between ranks by their measured speed (timings, so a different
// cut in every run): the boids stay bitwise those of one rank with the even cut. Tolerance 0 and
// a check every 4 steps: the take-off clusters the boids, so the cut moves on 2 and 3 ranks.
TEST(FlockLoadBalance, MovesTheCutAndChangesNoBit) {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const auto sch = schema();
  const std::string dir = "flock_balance_np" + std::to_string(size);
  const auto off =
      core::Config::from_string(sch, kDeck, "flock_balance.toml", {"flock.balance.interval=0"});
  const auto on =
      core::Config::from_string(sch, kDeck, "flock_balance.toml",
                                {"flock.balance.interval=4", "flock.balance.tolerance=0.0"});
  constexpr int kSteps = 80;
  MPI_Comm solo;
  MPI_Comm_split(MPI_COMM_WORLD, rank == 0 ? 0 : MPI_UNDEFINED, 0, &solo);
  std::vector<scenarios::BoidRecord> ref;
  if (rank == 0) ref = run(solo, off, kSteps, dir + "/serial", "", "", nullptr);
  std::size_t n = ref.size();
  MPI_Bcast(&n, sizeof n, MPI_BYTE, 0, MPI_COMM_WORLD);
  ref.resize(n);
  MPI_Bcast(ref.data(), static_cast<int>(n * sizeof(scenarios::BoidRecord)), MPI_BYTE, 0,
            MPI_COMM_WORLD);
  core::Timers timers;
  scenarios::RunContext ctx{MPI_COMM_WORLD, on, timers, dir + "/balanced"};
  scenarios::FlockScenario sc(ctx);
  const core::Index3 even = sc.local_first_cell();
  for (int k = 0; k < kSteps; ++k) sc.step();
  expect_same(ref, sc.gather_boids());
  if (size > 1) {
    EXPECT_GT(sc.balance_moves(), 0);
    int moved = !(sc.local_first_cell() == even);
    MPI_Allreduce(MPI_IN_PLACE, &moved, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    EXPECT_EQ(moved, 1) << "no rank's block starts elsewhere than in the even cut";
  } else {
    EXPECT_EQ(sc.balance_moves(), 0);
  }
  if (solo != MPI_COMM_NULL) MPI_Comm_free(&solo);
}

namespace {
std::string file_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}
}  // namespace

// Issue 8: the flock CSVs were appended on restart without dropping the rows written after the
// checkpoint. Run 20 steps, checkpoint, 10 more (rows of an abandoned future), then restart from
// the checkpoint in the same directory for 20 steps: both CSVs equal those of 40 steps straight.
TEST(FlockCsv, RestartDropsRowsAfterTheCheckpoint) {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const auto sch = schema();
  const auto cfg = core::Config::from_string(
      sch, kDeck, "flock_csv.toml", {"flock.stats_interval=3", "flock.predator.start_time=0.1"});
  const std::string dir = "flock_csv_np" + std::to_string(size);
  auto steps = [&](scenarios::FlockScenario& sc, int n) {
    for (int k = 0; k < n; ++k) sc.step();
  };
  core::Timers timers;
  {
    scenarios::RunContext ctx{MPI_COMM_WORLD, cfg, timers, dir + "/straight"};
    scenarios::FlockScenario sc(ctx);
    steps(sc, 40);
  }
  {
    scenarios::RunContext ctx{MPI_COMM_WORLD, cfg, timers, dir + "/restarted"};
    scenarios::FlockScenario sc(ctx);
    steps(sc, 20);
    sc.write_checkpoint(dir + "/at20.h5");
    steps(sc, 10);
  }
  {
    scenarios::RunContext ctx{MPI_COMM_WORLD, cfg, timers, dir + "/restarted"};
    scenarios::FlockScenario sc(ctx);
    sc.read_checkpoint(dir + "/at20.h5");
    steps(sc, 20);
  }
  if (rank == 0) {
    for (const char* name : {"/flock_order.csv", "/flock_avalanches.csv"}) {
      const std::string a = file_text(dir + "/straight" + name);
      const std::string b = file_text(dir + "/restarted" + name);
      EXPECT_GT(std::count(a.begin(), a.end(), '\n'), 1) << name << " has no rows";
      EXPECT_EQ(a, b) << name;
    }
  }
}

// Issue 8: the replicated sandpile's own L^3 decomposition aborted for L smaller than the rank
// count (flock.sandpile.size = 1 on 2 ranks). Build, step, write output and a checkpoint.
TEST(FlockSandpile, SmallerThanTheRankCount) {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const auto sch = schema();
  const auto cfg = core::Config::from_string(sch, kDeck, "flock_small.toml",
                                             {"flock.sandpile.size=1", "flock.sandpile.warmup=10"});
  const std::string dir = "flock_small_np" + std::to_string(size);
  core::Timers timers;
  scenarios::RunContext ctx{MPI_COMM_WORLD, cfg, timers, dir};
  scenarios::FlockScenario sc(ctx);
  for (int k = 0; k < 5; ++k) sc.step();
  sc.write_output();
  sc.write_checkpoint(dir + "/ckpt.h5");
  EXPECT_EQ(sc.gather_boids().size(), 2u);  // 1 prey (L^3) + 1 predator
  MPI_Barrier(MPI_COMM_WORLD);
  EXPECT_TRUE(std::filesystem::exists(dir + "/flock_sandpile_000005.h5"));
}
