#include "app/lbm_bench.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <string>
#include <vector>

#include "grid/decomposition.hpp"
#include "grid/field.hpp"
#include "solvers/lbm/lbm_solver.hpp"

namespace biota::app {
namespace {

// STREAM triad a = b + s c on every rank at once (ranks share the memory bus), best of 5.
// Returns the aggregate bandwidth in GB/s counting 24 bytes per element (STREAM convention).
double stream_triad(MPI_Comm comm) {
  const std::size_t n = 20'000'000;
  std::vector<double, grid::AlignedAllocator<double>> a(n, 0.0), b(n, 1.0), c(n, 2.0);
  double best = 1e30;
  for (int rep = 0; rep < 5; ++rep) {
    MPI_Barrier(comm);
    const double t0 = MPI_Wtime();
    const double s = 3.0 + rep;
    double* __restrict pa = a.data();
    const double* __restrict pb = b.data();
    const double* __restrict pc = c.data();
    for (std::size_t i = 0; i < n; ++i) pa[i] = pb[i] + s * pc[i];
    MPI_Barrier(comm);
    best = std::min(best, MPI_Wtime() - t0);
  }
  volatile double sink = a[n / 2];
  (void)sink;
  int size = 1;
  MPI_Comm_size(comm, &size);
  return 24.0 * n * size / best / 1e9;
}

struct Case {
  const char* lattice;
  const char* collision;
};

}  // namespace

int run_lbm_bench(MPI_Comm comm, const LbmBenchOptions& opts) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const double bw = stream_triad(comm);
  if (rank == 0) {
    fmt::print("biota bench lbm: {}^3 cells, {} ranks, {} timed steps per case\n", opts.size, size,
               opts.steps);
    fmt::print("STREAM triad (all ranks at once): {:.2f} GB/s\n", bw);
    fmt::print("{:<6} {:<4} {:>9} {:>11} {:>11} {:>9} {:>9} {:>9}\n", "lattice", "coll", "MLUPS",
               "roof(16Q)", "roof(24Q)", "%16Q", "%24Q", "halo%");
  }
  for (Case c :
       {Case{"D3Q15", "bgk"}, Case{"D3Q15", "trt"}, Case{"D3Q19", "bgk"}, Case{"D3Q19", "trt"}}) {
    const std::string name = std::string(c.lattice) + "/" + c.collision;
    if (!opts.cases.empty() &&
        std::find(opts.cases.begin(), opts.cases.end(), name) == opts.cases.end())
      continue;
    // The tank configuration: walls, free-slip top, inlet jet, outlet annulus, Guo forcing on.
    solvers::lbm::LbmParams p;
    p.lattice = c.lattice;
    p.trt = std::string(c.collision) == "trt";
    p.cells = {opts.size, opts.size, opts.size};
    p.dx = 1.0 / opts.size;
    p.dt = 1.0 / 600.0;
    p.viscosity = 0.033 / 3.0 * p.dx * p.dx / p.dt;
    using solvers::lbm::FaceType;
    p.faces = {FaceType::kWall, FaceType::kWall, FaceType::kWall,
               FaceType::kWall, FaceType::kWall, FaceType::kFreeSlip};
    p.inlet.face = 4;
    p.inlet.center[0] = p.inlet.center[1] = 0.5;
    p.inlet.radius = 0.08;
    p.inlet.speed = 0.3;
    p.outlet.face = 4;
    p.outlet.center[0] = p.outlet.center[1] = 0.5;
    p.outlet.r_min = 0.35;
    p.body_force = {0, 0, -1e-3};
    grid::Decomposition decomp(comm, p.cells, p.periodic());
    solvers::lbm::LbmSolver lbm(decomp, p);
    lbm.enable_force_field();
    for (int s = 0; s < 10; ++s) lbm.step(false);  // warm-up
    const double h0 = lbm.time_halo();
    MPI_Barrier(comm);
    const double t0 = MPI_Wtime();
    for (int s = 0; s < opts.steps; ++s) lbm.step(false);
    MPI_Barrier(comm);
    const double t = MPI_Wtime() - t0;
    double halo = lbm.time_halo() - h0, halo_max = 0;
    MPI_Allreduce(&halo, &halo_max, 1, MPI_DOUBLE, MPI_MAX, comm);
    const double mlups = double(opts.size) * opts.size * opts.size * opts.steps / t / 1e6;
    const int q = lbm.q();
    // 16Q: read Q + write Q doubles (the in-place bound); 24Q adds the write-allocate of the
    // second buffer that a two-grid scheme without non-temporal stores pays.
    const double roof16 = bw * 1e9 / (16.0 * q) / 1e6, roof24 = bw * 1e9 / (24.0 * q) / 1e6;
    if (rank == 0)
      fmt::print("{:<6} {:<4} {:>9.1f} {:>11.1f} {:>11.1f} {:>8.0f}% {:>8.0f}% {:>8.1f}%\n",
                 c.lattice, c.collision, mlups, roof16, roof24, 100 * mlups / roof16,
                 100 * mlups / roof24, 100 * halo_max / t);
  }
  return 0;
}

}  // namespace biota::app
