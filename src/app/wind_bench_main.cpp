/// \file wind_bench_main.cpp
/// \brief `biota_bench_wind`: step-time breakdown of the MAC wind solver (advection, diffusion,
/// Poisson, correction, halo, boundaries) and Poisson iterations/time per solve; plus a Poisson
/// grid sweep (manufactured solution) for the multigrid iteration counts. Not a test.
///
///   mpiexec -n 2 build/biota_bench_wind --size 100 --steps 5 [--sweep 32,64,128] -- <PETSc opts>
///   mpiexec -n 2 build/biota_bench_wind --size 100 --steps 3 --compare   # the preconditioners
///
/// `--compare` runs the step case (and the sweep, if given) once per preconditioner of CG in one
/// run: GAMG, BoomerAMG, the cell-centred PCMG, hypre's PFMG and our matrix-free geometric
/// multigrid (the default), each the peer of the others.
#include <fmt/format.h>
#include <mpi.h>

#include <CLI/CLI.hpp>

#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "core/agreement.hpp"
#include "core/error.hpp"
#include "core/memory.hpp"
#include "core/timers.hpp"
#include "grid/halo_exchange.hpp"
#include "linalg/petsc_environment.hpp"
#include "linalg/poisson_solver.hpp"
#include "solvers/mac/mac_solver.hpp"

using namespace biota;
using namespace biota::solvers::mac;

namespace {
double max_over_ranks(double v) {
  double g = 0;
  MPI_Allreduce(&v, &g, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  return g;
}

struct StepResult {
  double seconds_per_step = 0, iterations_per_solve = 0, seconds_per_solve = 0, divergence = 0;
  double setup_seconds = 0;
};

StepResult step_breakdown(int n, int steps, bool root, const std::string& options = "") {
  MacParams p;
  p.poisson_options = options;
  p.poisson_options_key = "--compare";
  p.cells = {n, n, n};
  p.dx = 0.2;
  auto& b = p.boundaries;
  b[0][0].type = BoundaryType::kInflow;
  b[0][1].type = BoundaryType::kConvectiveOutflow;
  b[1][0].type = b[1][1].type = BoundaryType::kPeriodic;
  b[2][0].type = BoundaryType::kGround;
  b[2][1].type = BoundaryType::kFreeSlip;
  p.inflow.kind = InflowProfile::kLog;
  p.inflow.speed = 5;
  p.solid = [n](const core::Index3& c) {  // a block standing in for the tree
    return c.x >= n / 4 && c.x < n / 4 + n / 10 && c.y >= 2 * n / 5 && c.y < 3 * n / 5 &&
           c.z < n / 3;
  };
  grid::Decomposition d(MPI_COMM_WORLD, p.cells, {false, true, false});
  core::Timers warm, timers;
  const double ts = MPI_Wtime();
  MacSolver s(d, p, warm);
  const double setup = max_over_ranks(MPI_Wtime() - ts);
  s.project_initial();
  for (int i = 0; i < 3; ++i) s.step();  // develop the flow a little, warm caches
  MacSolver* sp = &s;
  // Re-time with fresh timers: copy state into a solver bound to `timers`.
  MacSolver t(d, p, timers);
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < d.local_cells().z; ++k)
      for (int j = 0; j < d.local_cells().y; ++j)
        for (int i = 0; i < d.local_cells().x; ++i)
          t.velocity()(i, j, k, c) = sp->velocity()(i, j, k, c);
  t.pressure() = sp->pressure();
  t.set_boundary_face_rows(sp->boundary_face_rows());
  t.refresh();
  timers = core::Timers();
  long long its = 0;
  double solve_s = 0;
  MPI_Barrier(MPI_COMM_WORLD);
  const double t0 = MPI_Wtime();
  for (int i = 0; i < steps; ++i) {
    t.step();
    its += t.last_stats().poisson_iterations;
    solve_s += t.last_stats().poisson_seconds;
  }
  const double wall = max_over_ranks(MPI_Wtime() - t0);
  const int solves = steps * (p.scheme == TimeScheme::kRK2 ? 2 : 1);
  if (root) {
    std::printf("\n== MAC step at %d^3 on %d rank(s): %d steps (RK2: 2 projections/step), %s\n", n,
                d.size(), steps, t.poisson_description().c_str());
    std::printf("%-18s %12s %8s\n", "section", "s/step", "share");
  }
  double accounted = 0;
  for (const char* name : {"wind.advection", "wind.diffusion", "wind.poisson", "wind.correction",
                           "wind.halo", "wind.boundary"}) {
    const double v = max_over_ranks(timers.total(name)) / steps;
    accounted += v;
    if (root) std::printf("%-18s %12.4f %7.1f%%\n", name, v, 100 * v * steps / wall);
  }
  const double solve_per = max_over_ranks(solve_s) / solves;  // collective: outside `root`
  if (root) {
    std::printf("%-18s %12.4f %7.1f%%\n", "other (div, dt)", wall / steps - accounted,
                100 * (wall / steps - accounted) * steps / wall);
    std::printf("%-18s %12.4f\n", "total", wall / steps);
    std::printf(
        "Poisson: %.1f iterations/solve, %.4f s/solve (KSPSolve only), rel. divergence %.1e\n",
        double(its) / solves, solve_per, t.last_stats().max_divergence);
  }
  return {wall / steps, double(its) / solves, solve_per, t.last_stats().max_divergence, setup};
}

// The rank grid, the halo width and the memory of an N^3 case, before it runs (the step case is
// periodic along y, the sweep's cube is not); errors name `option` (one line, exit 2).
void check_size(int n, std::array<bool, 3> periodic, const std::string& option) {
  const grid::GridKeys keys{"", {option, option, option}};
  const grid::Decomposition d(MPI_COMM_WORLD, {n, n, n}, periodic, {0, 0, 0}, keys);
  grid::check_halo_width(d, MacSolver::kGhosts, keys);
  core::check_memory(MPI_COMM_WORLD, fmt::format("{} {}", option, n), MacSolver::memory_estimate(d),
                     fmt::format("{}^3 cells", n));
}

void poisson_sweep(const std::vector<int>& sizes, bool root, const std::string& options = "") {
  if (root)
    std::printf(
        "\n== Poisson sweep, Neumann cube, manufactured cos solution (options as given)\n"
        "%6s %10s %12s %12s %12s\n",
        "N", "its", "solve [s]", "setup+1 [s]", "max error");
  for (int N : sizes) {
    grid::Decomposition d(MPI_COMM_WORLD, {N, N, N}, {false, false, false});
    const double dx = 1.0 / N, pi = std::numbers::pi;
    const double ts = MPI_Wtime();
    linalg::PoissonSolver solver(d, dx,
                                 {{{linalg::PressureBC::kNeumann, linalg::PressureBC::kNeumann},
                                   {linalg::PressureBC::kNeumann, linalg::PressureBC::kNeumann},
                                   {linalg::PressureBC::kNeumann, linalg::PressureBC::kNeumann}}},
                                 nullptr, options, "--compare");
    const double setup = max_over_ranks(MPI_Wtime() - ts);
    const auto n = d.local_cells();
    const auto lo = d.local_box().lo;
    grid::Field<double> rhs(n, 1, 1), p(n, 1, 1);
    auto exact = [&](int i, int j, int k) {
      return std::cos(pi * (lo.x + i + 0.5) * dx) * std::cos(pi * (lo.y + j + 0.5) * dx) *
             std::cos(pi * (lo.z + k + 0.5) * dx);
    };
    for (int k = 0; k < n.z; ++k)
      for (int j = 0; j < n.y; ++j)
        for (int i = 0; i < n.x; ++i) rhs(i, j, k) = -3 * pi * pi * exact(i, j, k);
    auto st = solver.solve(rhs, p);
    double err = 0;
    for (int k = 0; k < n.z; ++k)
      for (int j = 0; j < n.y; ++j)
        for (int i = 0; i < n.x; ++i) err = std::max(err, std::fabs(p(i, j, k) - exact(i, j, k)));
    err = max_over_ranks(err);
    const double solve_s = max_over_ranks(st.seconds);
    if (root) std::printf("%6d %10d %12.4f %12.4f %12.3e\n", N, st.iterations, solve_s, setup, err);
  }
}
}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> petsc;
  int own = argc;
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "--") {
      own = i;
      for (int j = i + 1; j < argc; ++j) petsc.emplace_back(argv[j]);
      break;
    }
  MPI_Init(&argc, &argv);
  int size = 0, rank = 0;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  // Every rank parses the same arguments, so every rank stops alike; rank 0 prints.
  CLI::App cli{"biota_bench_wind: step time of the MAC wind solver and its pressure solves"};
  int n = 100, steps = 5;
  std::vector<int> sweep;
  bool compare = false;
  cli.add_option("--size", n, "cells per axis of the step case (0: only the --sweep)")
      ->check(CLI::Range(0, 100'000));
  cli.add_option("--steps", steps, "timed steps of the step case")->check(CLI::Range(1, 1'000'000));
  cli.add_option("--sweep", sweep, "Poisson sweep sizes, e.g. 32,64,128")
      ->delimiter(',')
      ->check(CLI::Range(1, 100'000));
  cli.add_flag("--compare", compare, "run every preconditioner of CG in turn");
  try {
    cli.parse(own, argv);
    if (n == 0 && sweep.empty())
      throw CLI::ValidationError(
          "--size 0 runs no step case and no --sweep is given: nothing to run");
  } catch (const CLI::ParseError& e) {
    int code = rank == 0 ? cli.exit(e) : e.get_exit_code();
    MPI_Finalize();
    return code == 0 ? 0 : core::kExitInput;
  }
  int code = 0;
  try {
    linalg::initialize(petsc);
    if (rank == 0)
      std::printf(
          "biota_bench_wind: %d rank(s), hardware threads %u; machine load not controlled\n", size,
          std::thread::hardware_concurrency());
    // Every size is checked before any case runs: a size the ranks cannot split, or the machine
    // cannot hold, stopped a run midway (std::bad_alloc on one rank).
    if (n > 0) check_size(n, {false, true, false}, "--size");
    for (int m : sweep) check_size(m, {false, false, false}, "--sweep");
    if (!compare) {
      if (n > 0) step_breakdown(n, steps, rank == 0);
      if (!sweep.empty()) poisson_sweep(sweep, rank == 0);
    } else {
      // Each configuration in turn; its options are removed before the next one is set.
      const std::vector<std::pair<std::string, std::string>> configs = {
          {"GAMG", "-poisson_pc_type gamg"},
          {"BoomerAMG", "-poisson_pc_type hypre"},
          {"PCMG cell-centred", "-poisson_pc_type mg"},
          {"PFMG", "-poisson_pc_type pfmg"},
          {"GMG matrix-free", "-poisson_pc_type gmg"}};
      std::vector<StepResult> results;
      for (const auto& [name, opts] : configs) {
        if (rank == 0) std::printf("\n#### %s (%s)\n", name.c_str(), opts.c_str());
        if (n > 0) results.push_back(step_breakdown(n, steps, rank == 0, opts));
        if (!sweep.empty()) poisson_sweep(sweep, rank == 0, opts);
        linalg::clear_options(opts);
      }
      if (rank == 0 && n > 0) {
        std::printf("\n== comparison at %d^3 on %d rank(s), %d steps each\n", n, size, steps);
        std::printf("%-20s %10s %10s %10s %10s %10s\n", "preconditioner", "s/step", "its/solve",
                    "s/solve", "setup [s]", "rel. div");
        for (std::size_t c = 0; c < results.size(); ++c)
          std::printf("%-20s %10.4f %10.1f %10.4f %10.3f %10.1e\n", configs[c].first.c_str(),
                      results[c].seconds_per_step, results[c].iterations_per_solve,
                      results[c].seconds_per_solve, results[c].setup_seconds,
                      results[c].divergence);
      }
    }
  } catch (const std::exception& e) {
    if (rank == 0) std::fprintf(stderr, "biota_bench_wind: error: %s\n", e.what());
    code = core::exit_code_of(e);
  }
  linalg::finalize();
  MPI_Finalize();
  return code;
}
