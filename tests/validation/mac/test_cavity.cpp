// Lid-driven cavity at Re = 100 (2D: one periodic cell in z) against Ghia, Ghia & Shin (1982),
// J. Comput. Phys. 48, 387-411, Table I (u on the vertical centreline) and Table II (v on the
// horizontal centreline). Target: every tabulated point within 2% of the lid speed. The case is
// the shipped deck input/cavity.toml (its [wind] tables: size, moving lid, Re -> viscosity).
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "core/config.hpp"

#include "linalg/petsc_environment.hpp"
#include "scenarios/wind_scenario.hpp"
#include "solvers/mac/mac_solver.hpp"

using namespace biota;
using namespace biota::solvers::mac;

namespace {
class PetscEnv : public ::testing::Environment {
 public:
  void TearDown() override { linalg::finalize(); }
};
const auto* env = ::testing::AddGlobalTestEnvironment(new PetscEnv);

// Table I, Re = 100: y, u(0.5, y)
const double kGhiaU[][2] = {{1.0000, 1.00000},  {0.9766, 0.84123},  {0.9688, 0.78871},
                            {0.9609, 0.73722},  {0.9531, 0.68717},  {0.8516, 0.23151},
                            {0.7344, 0.00332},  {0.6172, -0.13641}, {0.5000, -0.20581},
                            {0.4531, -0.21090}, {0.2813, -0.15662}, {0.1719, -0.10150},
                            {0.1016, -0.06434}, {0.0703, -0.04775}, {0.0625, -0.04192},
                            {0.0547, -0.03717}, {0.0000, 0.00000}};
// Table II, Re = 100: x, v(x, 0.5)
const double kGhiaV[][2] = {{1.0000, 0.00000},  {0.9688, -0.05906}, {0.9609, -0.07391},
                            {0.9531, -0.08864}, {0.9453, -0.10313}, {0.9063, -0.16914},
                            {0.8594, -0.22445}, {0.8047, -0.24533}, {0.5000, 0.05454},
                            {0.2344, 0.17527},  {0.2266, 0.17507},  {0.1563, 0.16077},
                            {0.0938, 0.12317},  {0.0781, 0.10890},  {0.0703, 0.10091},
                            {0.0625, 0.09233},  {0.0000, 0.00000}};

/// Linear interpolation of samples at positions (m + 0.5) h, m = 0..N-1, with wall values at 0
/// and 1.
double sample(const std::vector<double>& f, double pos, double wall_lo, double wall_hi) {
  const int N = static_cast<int>(f.size());
  const double s = pos * N - 0.5;
  if (s <= 0) return wall_lo + (f[0] - wall_lo) * (pos * N) / 0.5;
  if (s >= N - 1) return f[N - 1] + (wall_hi - f[N - 1]) * (s - (N - 1)) / 0.5;
  const int m = static_cast<int>(s);
  return f[m] + (f[m + 1] - f[m]) * (s - m);
}

/// The deck's `scenario` line and [wind...] tables (run/output keys belong to the app's schema).
std::string wind_tables(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  std::ostringstream out;
  bool keep = true;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line[0] == '[') keep = line.rfind("[wind", 0) == 0;
    if (keep && (line.rfind("seed", 0) == 0)) continue;
    if (keep) out << line << "\n";
  }
  return out.str();
}
}  // namespace

TEST(Cavity, Re100MatchesGhia) {
  core::ConfigSchema schema;
  schema.add_string("scenario", std::nullopt, {"wind"}, "scenario");
  scenarios::WindScenario::declare_config(schema);
  const std::string deck = BIOTA_SOURCE_DIR "/input/cavity.toml";
  const auto cfg = core::Config::from_string(schema, wind_tables(deck), deck);
  const MacParams p = scenarios::wind_params_from_config(cfg);
  const int N = p.cells.x;
  ASSERT_EQ(p.cells.y, N);
  ASSERT_DOUBLE_EQ(p.cells.x * p.dx, 1.0);                    // unit square
  ASSERT_DOUBLE_EQ(p.boundaries[1][1].wall_velocity.x, 1.0);  // lid speed 1
  ASSERT_DOUBLE_EQ(p.viscosity, 1.0 / 100);                   // Re = U L / nu = 100
  grid::Decomposition d(MPI_COMM_WORLD, p.cells, {false, false, true});
  ASSERT_EQ(d.size(), 1) << "serial test";
  core::Timers t;
  MacSolver s(d, p, t);
  // March to steady state: stop when u changes by < 2e-4 (of the lid speed) per unit time.
  double change = 1;
  std::vector<double> prev(N * N, 0.0);
  while (s.time() < 30 && change > 2e-4) {
    const double t0 = s.time();
    while (s.time() - t0 < 1.0) s.step();
    change = 0;
    for (int j = 0; j < N; ++j)
      for (int i = 0; i < N; ++i) {
        change = std::max(change, std::fabs(s.velocity()(i, j, 0, 0) - prev[j * N + i]));
        prev[j * N + i] = s.velocity()(i, j, 0, 0);
      }
    change /= (s.time() - t0);
  }
  std::printf("steady at t = %.1f (%lld steps, change %.1e per unit time)\n", s.time(),
              s.step_index(), change);
  std::vector<double> ucol(N), vrow(N);
  for (int j = 0; j < N; ++j) ucol[j] = s.velocity()(N / 2, j, 0, 0);  // u face at x = 0.5
  for (int i = 0; i < N; ++i) vrow[i] = s.velocity()(i, N / 2, 0, 1);  // v face at y = 0.5
  double eu = 0, ev = 0;
  for (const auto& r : kGhiaU) eu = std::max(eu, std::fabs(sample(ucol, r[0], 0, 1) - r[1]));
  for (const auto& r : kGhiaV) ev = std::max(ev, std::fabs(sample(vrow, r[0], 0, 0) - r[1]));
  std::printf("N=%d: max |u - Ghia| = %.4f, max |v - Ghia| = %.4f (lid speed 1)\n", N, eu, ev);
  EXPECT_LE(eu, 0.02);
  EXPECT_LE(ev, 0.02);
  EXPECT_LE(s.relative_divergence(), 1e-6);
}
