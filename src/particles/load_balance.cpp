#include "particles/load_balance.hpp"

#include <algorithm>
#include <cmath>

namespace biota::particles {

BalanceDecision rebalance_starts(const grid::Decomposition& d, const double* const x[3],
                                 const float* cost, std::size_t n, double dx,
                                 const core::Vec3& origin, double work_seconds, double work_units,
                                 double tolerance, int min_cells) {
  BalanceDecision out;
  const int P = d.size();
  if (P == 1) return out;
  const double mine[2] = {work_seconds, work_units};
  std::vector<double> all(2 * static_cast<std::size_t>(P));
  MPI_Allgather(mine, 2, MPI_DOUBLE, all.data(), 2, MPI_DOUBLE, d.comm());
  std::vector<double> speed(P);
  double slowest = 0, sum = 0;
  for (int r = 0; r < P; ++r) {
    const double t = all[2 * r], units = all[2 * r + 1];
    if (!(t > 0) || !(units > 0)) return out;  // nothing measured yet: keep the cut
    speed[r] = units / t;
    slowest = std::max(slowest, t);
    sum += t;
  }
  out.imbalance = slowest / (sum / P);
  if (out.imbalance <= 1 + tolerance) return out;
  // Estimated work per plane of cells along every split axis, summed over the ranks.
  const core::Index3 dims = d.dims(), cells = d.global_cells();
  std::array<std::vector<double>, 3> planes;
  for (int a = 0; a < 3; ++a) {
    if (dims[a] == 1) continue;
    planes[a].assign(cells[a], 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      const int c = static_cast<int>(std::floor((x[a][i] - origin[a]) / dx));
      planes[a][std::clamp(c, 0, cells[a] - 1)] += cost ? cost[i] : 1.0;
    }
    MPI_Allreduce(MPI_IN_PLACE, planes[a].data(), cells[a], MPI_DOUBLE, MPI_SUM, d.comm());
  }
  // weighted_block_starts directly, not balanced_block_starts: its floor of half an even block
  // suits grid work; particles may gather in a few planes, so only the ghost cutoff bounds a block.
  const auto capacity = grid::block_capacities(dims, speed);
  std::array<std::vector<int>, 3> starts;
  for (int a = 0; a < 3; ++a)
    if (dims[a] > 1) starts[a] = grid::weighted_block_starts(planes[a], capacity[a], min_cells);
  bool same = true;
  for (int a = 0; a < 3; ++a)
    for (std::size_t b = 0; b < starts[a].size(); ++b)
      same = same && starts[a][b] == d.block_start_of(a, static_cast<int>(b));
  if (!same) out.starts = std::move(starts);
  return out;
}

}  // namespace biota::particles
