#include "grid/two_phase_cut.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "grid/decomposition.hpp"

namespace biota::grid {

double two_phase_cost(const Index3& dims, const Index3& cells,
                      const std::array<std::vector<int>, 3>& starts,
                      const std::array<std::vector<double>, 3>& items, double item_cost,
                      const std::vector<double>& rank_speed) {
  // Per axis and block: its planes and its share of the items.
  std::array<std::vector<double>, 3> extent, share;
  double total = 0;
  for (int a = 0; a < 3; ++a)
    if (dims[a] > 1 && !items[a].empty())
      total = std::accumulate(items[a].begin(), items[a].end(), 0.0);
  for (int a = 0; a < 3; ++a) {
    extent[a].assign(dims[a], cells[a]);
    share[a].assign(dims[a], 1.0);
    if (dims[a] <= 1) continue;
    for (int b = 0; b < dims[a]; ++b) {
      const int lo = starts[a][b], hi = starts[a][b + 1];
      extent[a][b] = hi - lo;
      if (!items[a].empty() && total > 0)
        share[a][b] = std::accumulate(items[a].begin() + lo, items[a].begin() + hi, 0.0) / total;
    }
  }
  double max_cells = 0, max_items = 0;
  for (int r = 0; r < dims.product(); ++r) {
    // MPI_Cart_create without reorder numbers ranks row-major (the last axis fastest).
    const int c[3] = {r / (dims.y * dims.z), (r / dims.z) % dims.y, r % dims.z};
    const double speed = rank_speed.empty() ? 1.0 : rank_speed[r];
    double n_cells = 1, n_items = total;
    for (int a = 0; a < 3; ++a) n_cells *= extent[a][c[a]], n_items *= share[a][c[a]];
    max_cells = std::max(max_cells, n_cells / speed);
    max_items = std::max(max_items, n_items / speed);
  }
  return max_cells + item_cost * max_items;
}

std::array<std::vector<int>, 3> two_phase_block_starts(
    const Index3& dims, const Index3& cells, const std::array<std::vector<double>, 3>& items,
    double item_cost, const std::vector<double>& rank_speed, int min_cells) {
  std::array<std::vector<int>, 3> best;
  double best_cost = INFINITY;
  for (int k = -5; k <= 10; ++k) {
    const double w = k < -4 ? 0.0 : item_cost * std::ldexp(1.0, k);
    if (k > -5 && w <= 0) break;  // no item cost: equal cells only
    std::array<std::vector<double>, 3> weight;
    for (int a = 0; a < 3; ++a) {
      if (dims[a] <= 1) continue;
      const double cells_per_plane = double(cells.product()) / cells[a];
      weight[a].assign(cells[a], cells_per_plane);
      if (!items[a].empty())
        for (int p = 0; p < cells[a]; ++p) weight[a][p] += w * items[a][p];
    }
    auto starts = balanced_block_starts(dims, cells, weight, rank_speed, min_cells);
    const double cost = two_phase_cost(dims, cells, starts, items, item_cost, rank_speed);
    if (cost < best_cost) best_cost = cost, best = std::move(starts);
  }
  // The family above holds only cuts that balance some weighted sum; step each cut a plane at a
  // time while the cost falls (e.g. to the exact equal-items cut).
  for (bool moved = true; moved;) {
    moved = false;
    for (int a = 0; a < 3; ++a) {
      if (dims[a] <= 1) continue;
      const int thin = std::max(min_cells, cells[a] / dims[a] / 2);
      for (int b = 1; b < dims[a]; ++b)
        for (int step : {-1, 1}) {
          auto& s = best[a];
          while (s[b] + step - s[b - 1] >= thin && s[b + 1] - (s[b] + step) >= thin) {
            s[b] += step;
            const double cost = two_phase_cost(dims, cells, best, items, item_cost, rank_speed);
            if (cost < best_cost) {
              best_cost = cost, moved = true;
            } else {
              s[b] -= step;
              break;
            }
          }
        }
    }
  }
  return best;
}

}  // namespace biota::grid
