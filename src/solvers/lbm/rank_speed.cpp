#include "solvers/lbm/rank_speed.hpp"

#include <algorithm>

#include "grid/decomposition.hpp"

namespace biota::solvers::lbm {

std::vector<double> measure_rank_speeds(MPI_Comm comm, const LbmParams& params) {
  int size = 0;
  MPI_Comm_size(comm, &size);
  std::vector<double> speed(size, 1.0);
  if (size == 1) return speed;
  LbmParams box;  // the deck's lattice and collision; walls, no inlet, no force: same on all ranks
  box.lattice = params.lattice;
  box.trt = params.trt;
  box.magic = params.magic;
  // Beyond the last-level cache like a production block, but no larger than the deck's grid (a
  // small test tank should not pay for a big calibration).
  box.cells = {std::min(params.cells.x, 96), std::min(params.cells.y, 96),
               std::min(params.cells.z, 40)};
  box.dx = params.dx;
  box.dt = params.dt;
  box.density = params.density;
  box.viscosity = params.viscosity;
  box.faces.fill(FaceType::kWall);
  box.report_choices = false;
  std::vector<double> times;
  {
    grid::Decomposition self(MPI_COMM_SELF, box.cells, box.periodic());
    LbmSolver solver(self, box);
    solver.initialize([](const Index3&, double& rho, Vec3& u) { rho = 1, u = {}; });
    solver.advance(2, LbmSolver::PairMode::kFused);  // first touch, caches, clocks
    for (int rep = 0; rep < 5; ++rep) {
      MPI_Barrier(comm);  // all ranks sweep at once, as in the run
      const double t0 = MPI_Wtime();
      solver.advance(8, LbmSolver::PairMode::kFused);
      times.push_back(MPI_Wtime() - t0);
    }
  }
  // The median, not the best: a core shared with another task by time slices can run one short
  // repetition alone; its sustained speed is what the cut needs.
  std::nth_element(times.begin(), times.begin() + 2, times.end());
  const double median = times[2];
  const double mine = 1.0 / median;
  MPI_Allgather(&mine, 1, MPI_DOUBLE, speed.data(), 1, MPI_DOUBLE, comm);
  const double fastest = *std::max_element(speed.begin(), speed.end());
  // Within 10% of the fastest counts as equal: a cut moved by a timing blip would cost more than
  // the difference it balances.
  for (double& s : speed) s = s >= 0.9 * fastest ? 1.0 : s / fastest;
  return speed;
}

}  // namespace biota::solvers::lbm
