// The wind scenario: bad input gives one-line errors naming the key; a run restarted from an
// HDF5 checkpoint continues to the same fields.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <cstdio>

#include "core/config.hpp"
#include "core/error.hpp"
#include "core/timers.hpp"
#include "gather_fields.hpp"
#include "linalg/petsc_environment.hpp"
#include "scenarios/wind_scenario.hpp"

using namespace biota;

namespace {
class PetscEnv : public ::testing::Environment {
 public:
  void TearDown() override { linalg::finalize(); }
};
const auto* env = ::testing::AddGlobalTestEnvironment(new PetscEnv);

core::ConfigSchema schema() {
  core::ConfigSchema s;
  s.add_string("scenario", std::nullopt, {"wind"}, "scenario");
  scenarios::WindScenario::declare_config(s);
  return s;
}

const char* kDeck = R"(
scenario = "wind"
[wind]
nx = 24
ny = 8
nz = 10
dx = 0.5
step_time = 0.05
[wind.inflow]
reference_height = 3.0
)";

/// The error text of building the scenario from kDeck plus `extra` (TOML appended) and the
/// command-line solver options, or "" if it builds.
std::string error_of(const std::string& overrides, std::vector<std::string> solver_options = {}) {
  auto s = schema();
  try {
    auto cfg = core::Config::from_string(s, kDeck, "wind_test.toml", {overrides});
    core::Timers t;
    scenarios::RunContext ctx{MPI_COMM_WORLD, cfg, t, "/tmp", solver_options};
    scenarios::WindScenario w(ctx);
  } catch (const core::InputError& e) {
    return e.what();
  }
  return "";
}

void expect_one_line_naming(const std::string& msg, const std::string& what) {
  EXPECT_NE(msg.find(what), std::string::npos) << msg;
  EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  int rank;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank == 0) std::printf("  error: %s\n", msg.c_str());
}

std::vector<double> gather_velocity(scenarios::WindScenario& w) {
  auto v = w.solver().cell_velocity();
  auto p = w.solver().cell_pressure();
  v.insert(v.end(), p.begin(), p.end());
  // Same decomposition in both runs: compare rank-local arrays, reduce the maximum difference.
  return v;
}
}  // namespace

TEST(WindScenario, BadInputErrors) {
  expect_one_line_naming(error_of("wind.boundary.x_lo=\"slippy\""), "wind.boundary.x_lo");
  expect_one_line_naming(error_of("wind.cfl=1.5"), "wind.cfl");
  expect_one_line_naming(error_of("wind.viscosity=-1e-5"), "wind.viscosity");
  expect_one_line_naming(error_of("wind.poisson_options=\"-poisson_ksp_typo cg\""),
                         "-poisson_ksp_typo");
  expect_one_line_naming(error_of("wind.poisson_options=\"-poisson_ksp_typo cg\""),
                         "wind.poisson_options");
  expect_one_line_naming(error_of("wind.cfl=0.5", {"-poisson_pc_typo", "gamg"}),
                         "-poisson_pc_typo");
  // The geometric multigrid's own options are range-checked (they are not PETSc's).
  expect_one_line_naming(error_of("wind.poisson_options=\"-poisson_gmg_omega 2.5\""),
                         "-poisson_gmg_omega");
  expect_one_line_naming(error_of("wind.poisson_options=\"-poisson_gmg_sweeps 0\""), "[1, 100]");
  expect_one_line_naming(error_of("wind.boundary.y_lo=\"noslip\""), "wind.boundary.y_hi");
  EXPECT_EQ(error_of("wind.cfl=0.9"), "");
  // A valid command-line option is accepted.
  EXPECT_EQ(error_of("wind.cfl=0.5", {"-poisson_ksp_rtol", "1e-12"}), "");
}

TEST(WindScenario, RestartFromCheckpointContinues) {
  auto s = schema();
  auto cfg = core::Config::from_string(s, kDeck, "wind_test.toml");
  core::Timers t;
  scenarios::RunContext ctx{MPI_COMM_WORLD, cfg, t, "/tmp", {}};
  int size;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const std::string path = "/tmp/biota_test_wind_restart_np" + std::to_string(size) + ".h5";
  std::vector<double> a, b;
  double ta = 0;
  {
    scenarios::WindScenario w(ctx);
    for (int i = 0; i < 4; ++i) w.step();
    w.write_checkpoint(path);
    for (int i = 0; i < 4; ++i) w.step();
    a = gather_velocity(w);
    ta = w.time();
  }
  {
    scenarios::WindScenario w(ctx);
    w.read_checkpoint(path);
    EXPECT_EQ(w.step_index(), 4);
    for (int i = 0; i < 4; ++i) w.step();
    EXPECT_EQ(w.step_index(), 8);
    EXPECT_NEAR(w.time(), ta, 1e-12);
    b = gather_velocity(w);
  }
  ASSERT_EQ(a.size(), b.size());
  double d = 0, m = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    d = std::max(d, std::fabs(a[i] - b[i])), m = std::max(m, std::fabs(a[i]));
  double g[2] = {d, m}, gg[2];
  MPI_Allreduce(g, gg, 2, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  int rank;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank == 0)
    std::printf("restart from checkpoint: max difference %.3e of max %.3e\n", gg[0], gg[1]);
  EXPECT_EQ(gg[0], 0.0);
}

TEST(WindScenario, CheckpointReadOnOneRankContinues) {
  // Written on all ranks of the job, read back on rank 0 alone: the checkpoint does not depend on
  // the decomposition, and with the default pressure solve neither do the continuations (the
  // same bits; docs/wind.md, "Decomposition invariance").
  // PETSc start/stop is collective over the world: start it here so that neither scenario (one
  // of them lives on a sub-communicator) owns it.
  linalg::ensure_initialized();
  auto s = schema();
  auto cfg = core::Config::from_string(s, kDeck, "wind_test.toml");
  core::Timers t;
  int size, rank;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  const std::string path = "/tmp/biota_test_wind_ckpt_any_np" + std::to_string(size) + ".h5";
  std::vector<double> many;
  {
    scenarios::RunContext ctx{MPI_COMM_WORLD, cfg, t, "/tmp", {}};
    scenarios::WindScenario w(ctx);
    for (int i = 0; i < 3; ++i) w.step();
    w.write_checkpoint(path);
    for (int i = 0; i < 3; ++i) w.step();
    many = gather_global_fields(w.solver(), MPI_COMM_WORLD);
  }
  MPI_Comm solo;
  MPI_Comm_split(MPI_COMM_WORLD, rank == 0 ? 0 : MPI_UNDEFINED, 0, &solo);
  if (solo != MPI_COMM_NULL) {
    {
      scenarios::RunContext ctx{solo, cfg, t, "/tmp", {}};
      scenarios::WindScenario w(ctx);
      w.read_checkpoint(path);
      for (int i = 0; i < 3; ++i) w.step();
      auto one = gather_global_fields(w.solver(), solo);
      ASSERT_EQ(one.size(), many.size());
      double d = 0, m = 0;
      for (std::size_t i = 0; i < one.size(); ++i)
        d = std::max(d, std::fabs(one[i] - many[i])), m = std::max(m, std::fabs(many[i]));
      std::printf("checkpoint from %d rank(s) continued on 1 rank: max difference %.3e of %.3e\n",
                  size, d, m);
      EXPECT_EQ(d, 0.0);
    }
    MPI_Comm_free(&solo);
  }
  linalg::finalize();
}
