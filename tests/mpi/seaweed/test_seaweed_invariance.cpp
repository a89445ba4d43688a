/// \file test_seaweed_invariance.cpp
/// \brief The seaweed scenario (LBM + plants, two-way coupling) at reduced size gives bitwise the
/// same state on 1, 2 and 3 ranks, and a run of 2N steps equals N steps + checkpoint + restart on
/// another rank count + N steps (with an output step in between).
///
/// Run with 3 processes: the world is split into sub-communicators of 1, 2 and 3 ranks that run
/// one after the other; world rank 0 takes part in every run and compares the checkpoints (all
/// particle columns, sorted by global id, and the LBM populations).
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/timers.hpp"
#include "io/hdf5_util.hpp"
#include "scenarios/seaweed_scenario.hpp"

using namespace biota;

namespace {

const char* kDeck = R"(
[lbm]
lattice = "D3Q15"
collision = "bgk"
nx = 32
ny = 32
nz = 32
dx = 0.01
dt = 0.0016666666666666668
tau = 0.533
density = 998.0
[lbm.boundary]
x_lo = "wall"
x_hi = "wall"
y_lo = "wall"
y_hi = "wall"
z_lo = "wall"
z_hi = "free_slip"
[lbm.inlet]
face = "z_lo"
center = [0.16, 0.16]
radius = 0.04
speed = 0.3
profile = "parabolic"
ramp_time = 0.05
[lbm.outlet]
face = "z_lo"
type = "pressure"
center = [0.16, 0.16]
r_min = 0.12
[growth]
cycles = 3
env_radius = 0.12
[seaweed]
plants = 4
two_way = true
metrics_interval = 5
[seaweed.placement]
lo = [0.12, 0.12, 0.13]
hi = [0.20, 0.20, 0.19]
min_spacing = 0.05
)";

struct Snapshot {
  std::vector<std::vector<double>> rows;  // sorted by id
  std::vector<double> populations;
  int width = 0;
};

Snapshot read_snapshot(const std::string& path) {
  Snapshot s;
  hid_t f = io::h5::open_parallel(path, MPI_COMM_SELF);
  EXPECT_GE(f, 0) << path;
  auto d = io::h5::dims_of(f, "/rows/seaweed_particles");
  s.width = static_cast<int>(d[1]);
  std::vector<double> all(d[0] * d[1]);
  io::h5::read_block(f, "/rows/seaweed_particles", {0, 0}, {d[0], d[1]}, all.data());
  for (hsize_t r = 0; r < d[0]; ++r)
    s.rows.emplace_back(all.begin() + r * d[1], all.begin() + (r + 1) * d[1]);
  const int id_col = s.width - 3;  // u64 columns last: id, plant, parent
  std::sort(s.rows.begin(), s.rows.end(), [&](const auto& a, const auto& b) {
    return std::bit_cast<std::uint64_t>(a[id_col]) < std::bit_cast<std::uint64_t>(b[id_col]);
  });
  auto p = io::h5::dims_of(f, "/fields/lbm_populations");
  hsize_t n = 1;
  for (auto x : p) n *= x;
  s.populations.resize(n);
  std::vector<hsize_t> zero(p.size(), 0);
  io::h5::read_block(f, "/fields/lbm_populations", zero, p, s.populations.data());
  H5Fclose(f);
  return s;
}

// Number of differing values and the largest relative difference (u64 columns compared as bits).
struct Diff {
  long long differing = 0;
  double max_rel = 0;
};
Diff compare(const Snapshot& a, const Snapshot& b) {
  Diff d;
  EXPECT_EQ(a.rows.size(), b.rows.size());
  EXPECT_EQ(a.populations.size(), b.populations.size());
  auto one = [&](double x, double y) {
    if (std::memcmp(&x, &y, sizeof x) == 0) return;
    ++d.differing;
    const double den = std::max({std::abs(x), std::abs(y), 1e-300});
    d.max_rel = std::max(d.max_rel, std::isfinite(x) ? std::abs(x - y) / den : 1e300);
  };
  for (std::size_t r = 0; r < std::min(a.rows.size(), b.rows.size()); ++r)
    for (int c = 0; c < a.width; ++c) one(a.rows[r][c], b.rows[r][c]);
  for (std::size_t k = 0; k < std::min(a.populations.size(), b.populations.size()); ++k)
    one(a.populations[k], b.populations[k]);
  return d;
}

// Run on the first `np` world ranks: optionally restart from `restart`, advance to `steps`
// writing a checkpoint at every step listed in `ckpt_at`, an output step at `output_at`.
void run(int np, const std::string& dir, const std::string& restart, long long steps,
         const std::vector<std::pair<long long, std::string>>& ckpt_at, long long output_at,
         std::string* progress) {
  int world = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &world);
  MPI_Comm comm;
  MPI_Comm_split(MPI_COMM_WORLD, world < np ? 0 : MPI_UNDEFINED, world, &comm);
  if (comm != MPI_COMM_NULL) {
    core::ConfigSchema schema;
    scenarios::SeaweedScenario::declare_config(schema);
    auto cfg = core::Config::from_string(schema, kDeck, "invariance deck");
    core::Timers timers;
    scenarios::RunContext ctx{comm, cfg, timers, dir + "/out_np" + std::to_string(np)};
    scenarios::SeaweedScenario sc(ctx);
    if (!restart.empty()) sc.read_checkpoint(restart);
    while (sc.step_index() < steps) {
      sc.step();
      if (sc.step_index() == output_at) sc.write_output();
      for (const auto& [s, path] : ckpt_at)
        if (s == sc.step_index()) sc.write_checkpoint(path);
    }
    const std::string p = sc.progress();
    if (progress) *progress = p;
    MPI_Comm_free(&comm);
  }
  MPI_Barrier(MPI_COMM_WORLD);
}

}  // namespace

TEST(SeaweedInvariance, SameStateOnOneTwoThreeRanksAndAcrossRestart) {
  int world = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &world);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  ASSERT_EQ(size, 3) << "run with 3 processes";
  const auto dir = (std::filesystem::temp_directory_path() / "biota_seaweed_invariance").string();
  if (world == 0) {
    std::filesystem::remove_all(dir);
    for (int np = 1; np <= 3; ++np)  // the app creates output.dir/vtk; here the test does
      std::filesystem::create_directories(dir + "/out_np" + std::to_string(np) + "/vtk");
  }
  MPI_Barrier(MPI_COMM_WORLD);
  constexpr long long N = 20;
  auto ck = [&](const std::string& name) { return dir + "/" + name + ".h5"; };
  std::string prog1, prog3;
  // Decomposition invariance at step N (and the 3-rank run continues to 2N without a restart).
  run(1, dir, "", N, {{N, ck("np1_N")}}, -1, &prog1);
  run(2, dir, "", N, {{N, ck("np2_N")}}, -1, nullptr);
  run(3, dir, "", 2 * N, {{N, ck("np3_N")}, {2 * N, ck("np3_2N")}}, -1, &prog3);
  // Restart: the 1-rank checkpoint of step N continued on 2 ranks, with an output step between.
  run(2, dir, ck("np1_N"), 2 * N, {{2 * N, ck("restart_2N")}}, N + 5, nullptr);
  // Each rank reads only its share of the particle rows: restarts 1 -> 3 and 3 -> 2 ranks.
  run(3, dir, ck("np1_N"), 2 * N, {{2 * N, ck("restart13_2N")}}, -1, nullptr);
  run(2, dir, ck("np3_N"), 2 * N, {{2 * N, ck("restart32_2N")}}, -1, nullptr);
  if (world != 0) return;
  std::printf("state at step N on 1 rank: %s; at 2N on 3 ranks: %s\n", prog1.c_str(),
              prog3.c_str());
  const auto s1 = read_snapshot(ck("np1_N")), s2 = read_snapshot(ck("np2_N")),
             s3 = read_snapshot(ck("np3_N"));
  EXPECT_GT(s1.rows.size(), 100u);
  for (const auto& [name, other] : {std::pair{"2 ranks", &s2}, std::pair{"3 ranks", &s3}}) {
    const Diff d = compare(s1, *other);
    std::printf("1 rank vs %s at step %lld: %lld values differ, max relative difference %.3g\n",
                name, N, d.differing, d.max_rel);
    EXPECT_EQ(d.differing, 0) << name;
  }
  const Diff r = compare(read_snapshot(ck("np3_2N")), read_snapshot(ck("restart_2N")));
  std::printf(
      "2N straight (3 ranks) vs N (1 rank) + restart (2 ranks) + N: %lld values differ, "
      "max relative difference %.3g\n",
      r.differing, r.max_rel);
  EXPECT_EQ(r.differing, 0);
  for (const char* name : {"restart13_2N", "restart32_2N"}) {
    const Diff d = compare(read_snapshot(ck("np3_2N")), read_snapshot(ck(name)));
    std::printf("2N straight vs %s: %lld values differ\n", name, d.differing);
    EXPECT_EQ(d.differing, 0) << name;
  }
  // The restarted run's metrics CSV continues the time series (no second t = 0 row).
  std::ifstream csv(dir + "/out_np2/seaweed_clusters.csv");
  std::string line;
  int zero_rows = 0, rows = 0;
  double last_t = -1;
  bool monotone = true;
  std::getline(csv, line);
  while (std::getline(csv, line)) {
    const double t = std::stod(line.substr(0, line.find(',')));
    zero_rows += t == 0.0;
    ++rows;
    monotone = monotone && t > last_t;
    last_t = t;
  }
  EXPECT_EQ(zero_rows, 1);
  EXPECT_EQ(rows, 2 * N / 5 + 1);  // every 5 steps from t = 0, rows before the restart kept
  EXPECT_TRUE(monotone);
  EXPECT_NEAR(last_t, 2 * N / 60.0, 1e-8);
}
