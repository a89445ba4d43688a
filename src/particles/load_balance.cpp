#include "particles/load_balance.hpp"

#include <algorithm>

#include "grid/plane_weights.hpp"

namespace biota::particles {

namespace {

/// The slowest block's time, its weight over its capacity, under the cut `starts`.
double slowest_block(const std::vector<double>& prefix, const std::vector<double>& capacity,
                     const std::vector<int>& starts) {
  double t = 0;
  for (std::size_t b = 0; b + 1 < starts.size(); ++b)
    t = std::max(t, (prefix[starts[b + 1]] - prefix[starts[b]]) / capacity[b]);
  return t;
}

/// weighted_block_starts cuts where the running weight first reaches a block's share, so a heavy
/// plane always goes to the block before the cut. Move single cuts by one plane while that lowers
/// the slowest block's time (deterministic: every rank gets the same cut).
void refine_cuts(const std::vector<double>& weight, const std::vector<double>& capacity,
                 int min_cells, std::vector<int>& starts) {
  std::vector<double> prefix(weight.size() + 1, 0.0);
  for (std::size_t k = 0; k < weight.size(); ++k) prefix[k + 1] = prefix[k] + weight[k];
  double best = slowest_block(prefix, capacity, starts);
  for (bool moved = true; moved;) {
    moved = false;
    for (std::size_t i = 1; i + 1 < starts.size(); ++i)
      for (const int step : {-1, 1}) {
        const int k = starts[i] + step;
        if (k - starts[i - 1] < min_cells || starts[i + 1] - k < min_cells) continue;
        const int kept = starts[i];
        starts[i] = k;
        const double t = slowest_block(prefix, capacity, starts);
        if (t < best) {
          best = t;
          moved = true;
        } else {
          starts[i] = kept;
        }
      }
  }
}

}  // namespace

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
  const core::Index3 dims = d.dims();
  grid::PlaneWeights weights(dims, d.global_cells(), dx, origin);
  for (std::size_t i = 0; i < n; ++i)
    weights.add({x[0][i], x[1][i], x[2][i]}, cost ? cost[i] : 1.0);
  weights.sum_over(d.comm());
  const auto& planes = weights.planes();
  // weighted_block_starts directly, not balanced_block_starts: its floor of half an even block
  // suits grid work; particles may gather in a few planes, so only the ghost cutoff bounds a block.
  const auto capacity = grid::block_capacities(dims, speed);
  std::array<std::vector<int>, 3> starts;
  for (int a = 0; a < 3; ++a)
    if (dims[a] > 1) {
      starts[a] = grid::weighted_block_starts(planes[a], capacity[a], min_cells);
      refine_cuts(planes[a], capacity[a], min_cells, starts[a]);
    }
  bool same = true;
  for (int a = 0; a < 3; ++a)
    for (std::size_t b = 0; b < starts[a].size(); ++b)
      same = same && starts[a][b] == d.block_start_of(a, static_cast<int>(b));
  if (!same) out.starts = std::move(starts);
  return out;
}

}  // namespace biota::particles
