/// \file test_tree_scenario.cpp
/// \brief The tree scenario (node-link trees two-way coupled to the MAC wind) at reduced size:
///  - momentum: the force the trees add to the wind (sum over the MAC faces of the body force
///    times rho dx^3) equals -K_b times the sum of the wind forces F_w on the nodes, to round-off,
///    at every step of every run;
///  - one-way coupling (tree.two_way = false) leaves the wind bitwise equal to the wind scenario's;
///  - bitwise the same trees and wind on 1, 2 and 3 ranks, and N steps + checkpoint + restart on
///    another rank count + N steps equal to 2N steps (1 -> 3 and 3 -> 2 ranks), with the default
///    pressure solve (CG + the geometric multigrid, reproducible sums; docs/wind.md) and the
///    default convective outflow, on blocks that start at odd cells (16 cells on 3 ranks).
///
/// Two trees of the paper's rule (2 derivations, 3 m tall, planar, 5 cm apart so that their
/// crowns cross: branch contacts on) straddle rank boundaries on 2 and 3 ranks (and are owned by
/// different ranks on 3); one stands 0.1 m from the periodic y boundary (its branches have periodic
/// images) and 1 m above the ground (no node within a cell of a wall, so no weight lands on a wall
/// face). Run with 3 processes: the world is split into sub-communicators of 1, 2 and 3 ranks.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "core/timers.hpp"
#include "io/hdf5_util.hpp"
#include "linalg/petsc_environment.hpp"
#include "scenarios/tree_scenario.hpp"

using namespace biota;

namespace {

const char* kWind = R"(
[wind]
nx = 16
ny = 8
nz = 10
dx = 0.5
step_time = 0.03333333333333333
[wind.inflow]
profile = "uniform"
speed = 8.0
)";
const char* kTree = R"(
[tree]
count = 2
positions = [2.7, 0.1, 1.0, 3.05, 0.15, 1.0]
contacts = true
heights = [3.0, 3.0]
gravity = [0.0, 0.0, 0.0]
[tree.species1]
derivations = 2
)";

const std::string kDeck = std::string("scenario = \"tree\"\n") + kWind + kTree;
class PetscEnv : public ::testing::Environment {
 public:
  void TearDown() override { linalg::finalize(); }
};
const auto* env = ::testing::AddGlobalTestEnvironment(new PetscEnv);

std::string g_dir;

// The test directory with the paper's L-system file and the output directories (fresh: removed
// first). Collective over the world.
void prepare_dir(bool fresh) {
  int world = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &world);
  g_dir = (std::filesystem::temp_directory_path() / "biota_tree_invariance").string();
  if (world == 0) {
    if (fresh) std::filesystem::remove_all(g_dir);
    for (int np = 1; np <= 3; ++np)
      std::filesystem::create_directories(g_dir + "/out_np" + std::to_string(np) + "/vtk");
    std::filesystem::create_directories(g_dir + "/lsystems");
    std::ofstream(g_dir + "/lsystems/paper_fig1.lsys")
        << "axiom: F\nderivations: 2\nangle: 20\nF -> F[+F]F[-F][F]\n";
  }
  MPI_Barrier(MPI_COMM_WORLD);
}

core::Vec3 owned_force_sum(scenarios::TreeScenario& sc, MPI_Comm comm) {
  const auto& f = sc.solver().force();
  const auto n = f.cells();
  double s[3] = {0, 0, 0};
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < n.z; ++k)
      for (int j = 0; j < n.y; ++j)
        for (int i = 0; i < n.x; ++i) s[c] += f(i, j, k, c);
  MPI_Allreduce(MPI_IN_PLACE, s, 3, MPI_DOUBLE, MPI_SUM, comm);
  return {s[0], s[1], s[2]};
}

struct Snapshot {
  std::vector<double> nodes, wind;  // nodes sorted by (tree, node)
};

Snapshot read_snapshot(const std::string& path) {
  Snapshot s;
  hid_t f = io::h5::open_parallel(path, MPI_COMM_SELF);
  EXPECT_GE(f, 0) << path;
  auto d = io::h5::dims_of(f, "/rows/tree_nodes");
  std::vector<double> all(d[0] * d[1]);
  io::h5::read_block(f, "/rows/tree_nodes", {0, 0}, {d[0], d[1]}, all.data());
  std::vector<std::size_t> order(d[0]);
  for (std::size_t r = 0; r < d[0]; ++r) order[r] = r;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return std::pair(all[a * 8], all[a * 8 + 1]) < std::pair(all[b * 8], all[b * 8 + 1]);
  });
  for (auto r : order) s.nodes.insert(s.nodes.end(), &all[r * 8], &all[r * 8 + 8]);
  auto w = io::h5::dims_of(f, "/fields/wind_velocity");
  hsize_t n = 1;
  for (auto x : w) n *= x;
  s.wind.resize(n);
  std::vector<hsize_t> zero(w.size(), 0);
  io::h5::read_block(f, "/fields/wind_velocity", zero, w, s.wind.data());
  H5Fclose(f);
  return s;
}

long long differing(const std::vector<double>& a, const std::vector<double>& b) {
  EXPECT_EQ(a.size(), b.size());
  long long d = 0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i)
    d += std::memcmp(&a[i], &b[i], sizeof(double)) != 0;
  return d;
}

// Run on the first np world ranks: optionally restart, advance to `steps`, checkpoints at the
// listed steps; the momentum balance is asserted after every step.
void run(int np, const std::string& restart, long long steps,
         const std::vector<std::pair<long long, std::string>>& ckpt_at, double* tip = nullptr) {
  int world = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &world);
  MPI_Comm comm;
  MPI_Comm_split(MPI_COMM_WORLD, world < np ? 0 : MPI_UNDEFINED, world, &comm);
  if (comm != MPI_COMM_NULL) {
    core::ConfigSchema schema;
    schema.add_string("scenario", std::nullopt, {"tree"}, "scenario");
    scenarios::TreeScenario::declare_config(schema);
    auto cfg = core::Config::from_string(schema, kDeck, g_dir + "/tree_test.toml");
    core::Timers timers;
    const std::string out = g_dir + "/out_np" + std::to_string(np);
    scenarios::RunContext ctx{comm, cfg, timers, out};
    scenarios::TreeScenario sc(ctx);
    if (!restart.empty()) sc.read_checkpoint(restart);
    const double dx = sc.solver().params().dx;
    while (sc.step_index() < steps) {
      sc.step();
      const core::Vec3 grid = owned_force_sum(sc, comm) * (sc.air_density() * dx * dx * dx);
      const core::Vec3 fw = sc.total_wind_force();
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(grid[c], -sc.k_branch() * fw[c], 1e-13 * core::norm(fw))
            << "component " << c << " step " << sc.step_index() << " on " << np << " ranks";
      if (np == 1 && sc.step_index() == 1 && world == 0)
        std::printf(
            "momentum, step 1: wind force on the nodes (%.9g, %.9g, %.9g) N, added to "
            "the wind (%.9g, %.9g, %.9g) N, K_b = %g\n",
            fw.x, fw.y, fw.z, grid.x, grid.y, grid.z, sc.k_branch());
      for (const auto& [s, path] : ckpt_at)
        if (s == sc.step_index()) sc.write_checkpoint(path);
    }
    if (tip) {
      if (world == 0) std::printf("branch contacts in the last step: %lld\n", sc.last_contacts());
      EXPECT_GT(sc.last_contacts(), 0);  // the two trees touch
      double t = 0;
      for (std::size_t i = 0; i < sc.trees().size(); ++i) t = std::max(t, sc.tip_displacement(i));
      MPI_Allreduce(&t, tip, 1, MPI_DOUBLE, MPI_MAX, comm);
    }
    MPI_Comm_free(&comm);
  }
  MPI_Barrier(MPI_COMM_WORLD);
}

}  // namespace

TEST(TreeScenario, MomentumAndBitwiseOnOneTwoThreeRanksAndAcrossRestart) {
  int world = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &world);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  ASSERT_EQ(size, 3) << "run with 3 processes";
  linalg::ensure_initialized();  // PETSc start/stop is collective over the world
  prepare_dir(true);
  constexpr long long N = 6;
  auto ck = [&](const std::string& name) { return g_dir + "/" + name + ".h5"; };
  double tip1 = 0;
  run(1, "", 2 * N, {{N, ck("np1_N")}, {2 * N, ck("np1_2N")}}, &tip1);
  run(2, "", N, {{N, ck("np2_N")}});
  run(3, "", N, {{N, ck("np3_N")}});
  run(3, ck("np1_N"), 2 * N, {{2 * N, ck("restart13_2N")}});
  run(2, ck("np3_N"), 2 * N, {{2 * N, ck("restart32_2N")}});
  if (world == 0) {
    std::printf("largest tip displacement after %lld steps: %.6g m\n", 2 * N, tip1);
    EXPECT_GT(tip1, 1e-4);  // the trees did move
    const auto s1 = read_snapshot(ck("np1_N"));
    EXPECT_EQ(s1.nodes.size(), 8u * 2 * 26);  // 2 trees of 25 links + root
    for (const char* name : {"np2_N", "np3_N"}) {
      const auto s = read_snapshot(ck(name));
      const long long dn = differing(s1.nodes, s.nodes), dw = differing(s1.wind, s.wind);
      std::printf("1 rank vs %s: %lld node values and %lld wind values differ\n", name, dn, dw);
      EXPECT_EQ(dn, 0) << name;
      EXPECT_EQ(dw, 0) << name;
    }
    const auto s2 = read_snapshot(ck("np1_2N"));
    for (const char* name : {"restart13_2N", "restart32_2N"}) {
      const auto s = read_snapshot(ck(name));
      const long long dn = differing(s2.nodes, s.nodes), dw = differing(s2.wind, s.wind);
      std::printf("2N straight (1 rank) vs %s: %lld node values and %lld wind values differ\n",
                  name, dn, dw);
      EXPECT_EQ(dn, 0) << name;
      EXPECT_EQ(dw, 0) << name;
    }
  }
}

TEST(TreeScenario, PeriodicBoxMomentumChangesByTheReaction) {
  // A fully periodic box with a uniform 8 m/s wind and one explicit Euler solver step per
  // scenario step: advection and diffusion of the uniform field vanish, and the projection's
  // pressure gradient sums to zero over a periodic box, so the wind's momentum (sum over the
  // faces of u rho dx^3) changes in the first step by exactly dt times the force added,
  // -K_b dt sum F_w. (Later steps: the upwind advection is not in conservation form, so the
  // budget closes only to truncation error; not asserted.)
  linalg::ensure_initialized();
  prepare_dir(false);
  core::ConfigSchema schema;
  schema.add_string("scenario", std::nullopt, {"tree"}, "scenario");
  scenarios::TreeScenario::declare_config(schema);
  auto cfg = core::Config::from_string(
      schema, kDeck, g_dir + "/periodic.toml",
      {"wind.boundary.x_lo=\"periodic\"", "wind.boundary.x_hi=\"periodic\"",
       "wind.boundary.z_lo=\"periodic\"", "wind.boundary.z_hi=\"periodic\"",
       "wind.time_scheme=\"euler\"", "wind.step_time=0.025", "wind.initial_from_inflow=false",
       "wind.initial_velocity=[8.0, 0.0, 0.0]", "wind.poisson_options=\"\"",
       "tree.contacts=false"});
  core::Timers timers;
  scenarios::RunContext ctx{MPI_COMM_WORLD, cfg, timers, g_dir + "/out_np3"};
  scenarios::TreeScenario sc(ctx);
  auto momentum = [&] {
    const auto& u = sc.solver().velocity();
    double m[3] = {0, 0, 0};
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < u.cells().z; ++k)
        for (int j = 0; j < u.cells().y; ++j)
          for (int i = 0; i < u.cells().x; ++i) m[c] += u(i, j, k, c);
    MPI_Allreduce(MPI_IN_PLACE, m, 3, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    const double dx = sc.solver().params().dx, w = sc.air_density() * dx * dx * dx;
    return core::Vec3{m[0] * w, m[1] * w, m[2] * w};
  };
  const core::Vec3 before = momentum();
  sc.step();
  EXPECT_EQ(sc.solver().step_index(), 1);  // one solver step
  const core::Vec3 change = momentum() - before;
  const core::Vec3 expected = -sc.k_branch() * 0.025 * sc.total_wind_force();
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank == 0)
    std::printf(
        "periodic box: momentum change (%.12g, %.12g, %.12g) kg m/s, -K_b dt sum F_w "
        "(%.12g, %.12g, %.12g)\n",
        change.x, change.y, change.z, expected.x, expected.y, expected.z);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(change[c], expected[c], 1e-9 * core::norm(expected)) << "component " << c;
}

TEST(TreeScenario, OneWayLeavesTheWindOfTheWindScenario) {
  // tree.two_way = false: the same wind, bit for bit, as the wind scenario without trees.
  linalg::ensure_initialized();
  prepare_dir(false);
  std::vector<double> with_trees, without;
  core::Timers timers;
  for (int pass = 0; pass < 2; ++pass) {
    core::ConfigSchema schema;
    schema.add_string("scenario", std::nullopt, {"tree", "wind"}, "scenario");
    if (pass == 0)
      scenarios::TreeScenario::declare_config(schema);
    else
      scenarios::WindScenario::declare_config(schema);
    const std::string deck = pass == 0 ? kDeck : std::string("scenario = \"wind\"\n") + kWind;
    auto cfg = core::Config::from_string(
        schema, deck, g_dir + "/oneway.toml",
        pass == 0 ? std::vector<std::string>{"tree.two_way=false"} : std::vector<std::string>{});
    scenarios::RunContext ctx{MPI_COMM_WORLD, cfg, timers, g_dir + "/out_np3"};
    std::unique_ptr<scenarios::WindScenario> sc;
    if (pass == 0)
      sc = std::make_unique<scenarios::TreeScenario>(ctx);
    else
      sc = std::make_unique<scenarios::WindScenario>(ctx);
    for (int i = 0; i < 4; ++i) sc->step();
    const auto& u = sc->solver().velocity();
    auto& out = pass == 0 ? with_trees : without;
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < u.cells().z; ++k)
        for (int j = 0; j < u.cells().y; ++j)
          for (int i = 0; i < u.cells().x; ++i) out.push_back(u(i, j, k, c));
  }
  long long d = differing(with_trees, without);
  MPI_Allreduce(MPI_IN_PLACE, &d, 1, MPI_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_EQ(d, 0);
}
