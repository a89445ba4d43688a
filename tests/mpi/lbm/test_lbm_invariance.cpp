// Decomposition invariance and restart: the same run on 1 rank and on P ranks gives bitwise
// identical populations; N steps + checkpoint (on 1 rank) + restart (on P ranks) + N steps equals
// 2N steps.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <filesystem>
#include <tuple>

#include "io/checkpoint.hpp"
#include "solvers/lbm/lbm_solver.hpp"

using namespace biota;
using namespace biota::solvers::lbm;

namespace {

LbmParams tank_like(const std::string& lattice, bool trt) {
  LbmParams p;
  p.lattice = lattice;
  p.trt = trt;
  p.cells = {23, 19, 17};
  p.dx = 0.01;
  p.dt = 1.0 / 600;
  p.viscosity = 0.033 / 3 * p.dx * p.dx / p.dt;
  p.faces = {FaceType::kWall,     FaceType::kWall, FaceType::kPeriodic,
             FaceType::kPeriodic, FaceType::kWall, FaceType::kFreeSlip};
  p.inlet.face = 4;
  p.inlet.center[0] = 0.11;
  p.inlet.center[1] = 0.09;
  p.inlet.radius = 0.05;
  p.inlet.speed = 0.3;
  p.inlet.ramp_time = 0.02;
  p.inlet.pulse_amplitude = 0.2;
  p.outlet.face = 4;
  p.outlet.center[0] = 0.11;
  p.outlet.center[1] = 0.09;
  p.outlet.r_min = 0.08;
  p.body_force = {0, 1e-2, -2e-2};
  return p;
}

void setup(LbmSolver& lbm) {
  lbm.set_solid([](const core::Index3& g) { return g.x == 15 && g.y >= 4 && g.y < 8 && g.z < 9; });
  lbm.enable_force_field();
  const auto n = lbm.decomposition().local_cells();
  const auto lo = lbm.decomposition().local_box().lo;
  for (int k = 0; k < n.z; ++k)
    for (int j = 0; j < n.y; ++j)
      for (int i = 0; i < n.x; ++i)
        lbm.force()(i, j, k, 0) = 1e-5 * std::sin(0.7 * (lo.x + i) + 0.3 * (lo.y + j) + (lo.z + k));
}

std::string dir() {
  auto d = std::filesystem::temp_directory_path() / "biota_lbm_invariance";
  std::filesystem::create_directories(d);
  return d.string();
}

// Populations of a checkpoint, read on rank 0 alone.
std::vector<double> read_all(const LbmParams& p, const std::string& path) {
  grid::Decomposition d(MPI_COMM_SELF, p.cells, p.periodic());
  LbmSolver lbm(d, p);
  io::CheckpointReader r(d, path);
  lbm.read_checkpoint(r);
  std::vector<double> out;
  const auto n = p.cells;
  grid::Field<double> f(n, lbm.q(), 1);
  r.read_field("lbm_populations", f, 0, lbm.q());
  for (int q = 0; q < lbm.q(); ++q)
    for (int k = 0; k < n.z; ++k)
      for (int j = 0; j < n.y; ++j)
        for (int i = 0; i < n.x; ++i) out.push_back(f(i, j, k, q));
  return out;
}

std::vector<double> run_serial(const LbmParams& p, int steps, const std::string& ckpt_at_end) {
  grid::Decomposition d(MPI_COMM_SELF, p.cells, p.periodic());
  LbmSolver lbm(d, p);
  setup(lbm);
  for (int s = 0; s < steps; ++s) lbm.step(s % 3 == 0);
  io::CheckpointWriter w(d, ckpt_at_end);
  lbm.write_checkpoint(w);
  w.commit();
  return read_all(p, ckpt_at_end);
}

// Density and velocity of the owned cells, in cell order.
std::vector<double> owned_moments(const LbmSolver& lbm) {
  const auto n = lbm.decomposition().local_cells();
  std::vector<double> moments;
  for (int k = 0; k < n.z; ++k)
    for (int j = 0; j < n.y; ++j)
      for (int i = 0; i < n.x; ++i) {
        moments.push_back(lbm.density()(i, j, k));
        for (int c = 0; c < 3; ++c) moments.push_back(lbm.velocity()(i, j, k, c));
      }
  return moments;
}

class Invariance : public ::testing::TestWithParam<std::pair<const char*, bool>> {};

}  // namespace

// 2N steps on 1 and on all ranks, and N steps on 1 rank + checkpoint + N steps on all ranks, give
// the same bits. N odd: the checkpoint is written after a neighbour step of the in-place scheme.
// `dims`: the rank grid of the parallel runs (zeros: the default choice, x split for this box).
static void check_invariance(const char* lattice, bool trt, int N, core::Index3 dims = {0, 0, 0}) {
  const auto p = tank_like(lattice, trt);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const std::string base = dir() + "/" + lattice + (trt ? "_trt" : "_bgk") + "_N" +
                           std::to_string(N) + "_np" + std::to_string(size) + "_dims" +
                           std::to_string(dims.x) + std::to_string(dims.y) + std::to_string(dims.z);
  std::vector<double> serial;
  if (rank == 0) serial = run_serial(p, 2 * N, base + "_serial.h5");
  {
    grid::Decomposition d(MPI_COMM_WORLD, p.cells, p.periodic(), dims);
    LbmSolver lbm(d, p);
    setup(lbm);
    for (int s = 0; s < 2 * N; ++s) lbm.step(s % 3 == 0);
    io::CheckpointWriter w(d, base + "_parallel.h5");
    lbm.write_checkpoint(w);
    w.commit();
  }
  // Restart: N steps on rank 0 alone, checkpoint, continue on all ranks.
  if (rank == 0) run_serial(p, N, base + "_half.h5");
  MPI_Barrier(MPI_COMM_WORLD);
  {
    grid::Decomposition d(MPI_COMM_WORLD, p.cells, p.periodic(), dims);
    LbmSolver lbm(d, p);
    setup(lbm);
    io::CheckpointReader r(d, base + "_half.h5");
    lbm.read_checkpoint(r);
    EXPECT_EQ(lbm.step_index(), N);
    for (int s = N; s < 2 * N; ++s) lbm.step(s % 3 == 0);
    io::CheckpointWriter w(d, base + "_restarted.h5");
    lbm.write_checkpoint(w);
    w.commit();
  }
  if (rank == 0) {
    const auto parallel = read_all(p, base + "_parallel.h5");
    const auto restarted = read_all(p, base + "_restarted.h5");
    ASSERT_EQ(parallel.size(), serial.size());
    long long diff_par = 0, diff_rst = 0;
    for (size_t i = 0; i < serial.size(); ++i) {
      diff_par += parallel[i] != serial[i];
      diff_rst += restarted[i] != serial[i];
    }
    EXPECT_EQ(diff_par, 0) << "populations differing between 1 and " << size << " ranks";
    EXPECT_EQ(diff_rst, 0) << "populations differing after restart on " << size << " ranks";
    // The run did something: the jet moved the fluid.
    double dev = 0;
    for (double v : serial) dev += std::fabs(v);
    EXPECT_TRUE(std::isfinite(dev));
  }
}

TEST_P(Invariance, SameBitsOnOneAndManyRanks) {
  check_invariance(GetParam().first, GetParam().second, 40);
}

TEST_P(Invariance, CheckpointAfterAnOddStepRestartsBitwise) {
  check_invariance(GetParam().first, GetParam().second, 21);
}

// A y split (the default for cubes such as the tank: whole rows cross) and a z split (whole
// planes) give the same bits too, also across a checkpoint after a neighbour step.
TEST_P(Invariance, SameBitsWithAYSplit) {
  check_invariance(GetParam().first, GetParam().second, 40, {1, 0, 1});
}

TEST_P(Invariance, SameBitsWithAZSplit) {
  check_invariance(GetParam().first, GetParam().second, 21, {1, 1, 0});
}

// The sweep skips the force loads in the cells of a row outside its force span (every component
// +0). Against the same field with each +0 written as -0 (a -0 counts as carrying a force, so every
// cell loads it; uniform + (-0) and uniform + (+0) are the same number for these body forces):
// bitwise the same density and velocity after 7 steps (both parities); and the force in the
// spans acts.
TEST_P(Invariance, ForceSpansSkipOnlyZeroForces) {
  const auto [lattice, trt] = GetParam();
  const auto p = tank_like(lattice, trt);
  auto run = [&](double zero, bool with_force) {
    grid::Decomposition d(MPI_COMM_WORLD, p.cells, p.periodic());
    LbmSolver lbm(d, p);
    lbm.enable_force_field();
    const auto n = d.local_cells();
    const auto lo = d.local_box().lo;
    auto& f = lbm.force();
    f.fill(zero);
    for (int k = 0; k < n.z; ++k)
      for (int j = 0; j < n.y; ++j)
        for (int i = 0; i < n.x; ++i) {
          const core::Index3 g{lo.x + i, lo.y + j, lo.z + k};
          if (with_force && g.y >= 5 && g.y < 10 && g.x >= 3 && g.x < 14)
            f(i, j, k, 0) = 1e-4 * std::sin(0.7 * g.x + 0.3 * g.y + g.z);
          if (g.x == 20 && g.y == 2 && g.z == 3) f(i, j, k, 1) = -0.0;  // a lone -0: loaded
        }
    for (int s = 0; s < 7; ++s) lbm.step(s % 3 == 0);  // the last one stores the moments
    return owned_moments(lbm);
  };
  const auto spans = run(0.0, true), everywhere = run(-0.0, true), none = run(0.0, false);
  long long differ = 0, forced = 0;
  for (std::size_t c = 0; c < spans.size(); ++c) {
    differ += spans[c] != everywhere[c];
    forced += spans[c] != none[c];
  }
  long long sums[2] = {differ, forced};
  MPI_Allreduce(MPI_IN_PLACE, sums, 2, MPI_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_EQ(sums[0], 0) << "moments differing from the run that loads the force everywhere";
  EXPECT_GT(sums[1], 0) << "the force in the spans changed nothing";
}

// advance(n) fuses pairs of steps plane by plane: the same bits as n single steps, from either
// parity, with the tank's walls, free slip, pulsed inlet, outlet, solids, body force and force
// field; and in the automatic mode, which times both ways in its first pairs and keeps one (after
// the single steps' own trial of overlapping the halo exchange or not: 61 steps cover both; 1201
// steps also the repeated trials, every 500 pairs).
TEST_P(Invariance, FusedStepPairsGiveTheBitsOfSingleSteps) {
  const auto [lattice, trt] = GetParam();
  const auto p = tank_like(lattice, trt);
  using Mode = LbmSolver::PairMode;
  auto run = [&](Mode mode, int first, int n) {
    grid::Decomposition d(MPI_COMM_WORLD, p.cells, p.periodic(), {1, 0, 0});
    LbmSolver lbm(d, p);
    setup(lbm);
    for (int s = 0; s < first; ++s) lbm.step(false);
    if (mode == Mode::kSingle)
      for (int s = 0; s < n; ++s) lbm.step(false);
    else
      lbm.advance(n, mode);
    lbm.update_macroscopic();
    return owned_moments(lbm);
  };
  for (auto [first, n, mode] : {std::tuple{0, 9, Mode::kFused}, std::tuple{1, 9, Mode::kFused},
                                std::tuple{1, 61, Mode::kAuto}, std::tuple{0, 1201, Mode::kAuto}}) {
    const auto single = run(Mode::kSingle, first, n), other = run(mode, first, n);
    long long differ = 0;
    for (std::size_t c = 0; c < single.size(); ++c) differ += single[c] != other[c];
    MPI_Allreduce(MPI_IN_PLACE, &differ, 1, MPI_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
    EXPECT_EQ(differ, 0) << "moments differing after " << first << " + " << n << " steps ("
                         << (mode == Mode::kAuto ? "auto" : "fused") << ")";
  }
}

// The timed choices are collective even where ranks differ in what they can do: 7 cells along y
// on 3 ranks leave two ranks with 2 rows, too few to fuse, and one with 3. Through the trials
// (1201 steps, repeated trials included) no rank waits for a decision the others skip, and the
// bits are those of single steps.
TEST_P(Invariance, TimedChoicesOnRanksThatCannotAllFuse) {
  const auto [lattice, trt] = GetParam();
  auto p = tank_like(lattice, trt);
  p.cells = {23, 7, 17};
  p.inlet.center[1] = p.outlet.center[1] = 0.035;
  p.inlet.radius = 0.03;
  p.outlet.r_min = 0.05;
  using Mode = LbmSolver::PairMode;
  auto run = [&](Mode mode) {
    grid::Decomposition d(MPI_COMM_WORLD, p.cells, p.periodic(), {1, 0, 1});
    LbmSolver lbm(d, p);
    setup(lbm);
    if (mode == Mode::kSingle)
      for (int s = 0; s < 1201; ++s) lbm.step(false);
    else
      lbm.advance(1201, mode);
    lbm.update_macroscopic();
    return owned_moments(lbm);
  };
  const auto single = run(Mode::kSingle), automatic = run(Mode::kAuto);
  long long differ = 0;
  for (std::size_t c = 0; c < single.size(); ++c) differ += single[c] != automatic[c];
  MPI_Allreduce(MPI_IN_PLACE, &differ, 1, MPI_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_EQ(differ, 0) << "moments differing between automatic pairs and single steps";
}

// The timed choice: warm-up uses take the initial way, the trial alternates starting with `true`,
// the faster way by its fastest use wins (the slowest rank's time counts), and the trial repeats
// every period, so a later change of speed changes the choice.
TEST(TimedChoice, AlternatesDecidesAndRetries) {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  TimedChoice choice(2, 3, 20, false);
  auto use = [&](double t_true, double t_false) {
    const bool way = choice.pick();
    // Rank 0 is slower on `true`: its times must decide on every rank.
    const double t = way ? t_true * (rank == 0 ? 1.5 : 1.0) : t_false;
    return std::pair{way, choice.record(way, t, MPI_COMM_WORLD)};
  };
  EXPECT_FALSE(use(1.0, 1.2).first);  // warm-up: the initial way
  EXPECT_FALSE(use(1.0, 1.2).first);
  bool ways[6], reported = false;
  for (bool& w : ways) {
    const auto [way, report] = use(1.0, 1.2);  // `true` takes 1.5 s on rank 0: `false` wins
    w = way, reported = reported || report;
  }
  EXPECT_TRUE(ways[0] && !ways[1] && ways[2] && !ways[3] && ways[4] && !ways[5]);
  EXPECT_TRUE(reported);  // the first decision is reported
  EXPECT_FALSE(choice.chosen());
  EXPECT_DOUBLE_EQ(choice.best(true), 1.5);
  for (int u = 8; u < 20; ++u) EXPECT_FALSE(use(1.0, 1.2).first);  // the choice holds
  for (int u = 0; u < 8; ++u) use(0.5, 1.2);  // the next trial: `true` now takes 0.75 s
  EXPECT_TRUE(choice.chosen());
}

INSTANTIATE_TEST_SUITE_P(Lattices, Invariance,
                         ::testing::Values(std::make_pair("D3Q15", false),
                                           std::make_pair("D3Q19", true)));
