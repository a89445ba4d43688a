#pragma once
/// \file cell_list.hpp
/// \brief O(N) neighbour search: particles binned into cubic cells of edge >= cutoff; pairs are
/// found by visiting the 27 surrounding bins (13 forward bins + own bin for a half list).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "core/types.hpp"

namespace biota::particles {

/// \brief Bins of the points [0, n); rebuilt whenever the points move by more than a skin.
class CellList {
 public:
  /// \brief Bin `n` points given by coordinate arrays x, y, z with bins of edge >= `cutoff`.
  CellList(const core::Real* x, const core::Real* y, const core::Real* z, std::size_t n,
           core::Real cutoff)
      : x_(x), y_(y), z_(z), n_(n), cutoff_(cutoff) {
    if (n == 0) return;
    core::Vec3 lo{x[0], y[0], z[0]}, hi = lo;
    for (std::size_t i = 0; i < n; ++i) {
      lo = {std::min(lo.x, x[i]), std::min(lo.y, y[i]), std::min(lo.z, z[i])};
      hi = {std::max(hi.x, x[i]), std::max(hi.y, y[i]), std::max(hi.z, z[i])};
    }
    lo_ = lo;
    for (int d = 0; d < 3; ++d) {
      // Cap the bin count so a sparse, widely spread set cannot allocate a huge grid.
      nb_[d] = std::max(1, std::min(256, static_cast<int>((hi[d] - lo[d]) / cutoff) + 1));
      edge_[d] = std::max(cutoff, (hi[d] - lo[d]) / nb_[d] * (1 + 1e-12));
      if (edge_[d] <= 0) edge_[d] = 1;
    }
    head_.assign(static_cast<std::size_t>(nb_[0]) * nb_[1] * nb_[2] + 1, 0);
    bin_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      bin_[i] = bin_of(i);
      ++head_[bin_[i] + 1];
    }
    for (std::size_t b = 1; b < head_.size(); ++b) head_[b] += head_[b - 1];
    order_.resize(n);
    std::vector<std::size_t> fill(head_.begin(), head_.end() - 1);
    for (std::size_t i = 0; i < n; ++i) order_[fill[bin_[i]]++] = i;
    // Coordinates copied in bin order: the pair loop streams them instead of gathering.
    sx_.resize(n), sy_.resize(n), sz_.resize(n);
    for (std::size_t a = 0; a < n; ++a)
      sx_[a] = x[order_[a]], sy_[a] = y[order_[a]], sz_[a] = z[order_[a]];
  }

  /// \brief Call f(i, j, r2) once for every unordered pair i != j closer than the cutoff.
  template <class F>
  void for_each_pair(F&& f) const {
    if (n_ == 0) return;
    const core::Real rc2 = cutoff_ * cutoff_;
    for (int bz = 0; bz < nb_[2]; ++bz)
      for (int by = 0; by < nb_[1]; ++by)
        for (int bx = 0; bx < nb_[0]; ++bx) {
          const std::size_t b = index(bx, by, bz);
          if (head_[b] == head_[b + 1]) continue;  // sparse sets: most bins are empty
          for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
              for (int dx = -1; dx <= 1; ++dx) {
                const int cx = bx + dx, cy = by + dy, cz = bz + dz;
                if (cx < 0 || cy < 0 || cz < 0 || cx >= nb_[0] || cy >= nb_[1] || cz >= nb_[2])
                  continue;
                const std::size_t c = index(cx, cy, cz);
                if (c < b) continue;  // each bin pair once
                for (std::size_t a = head_[b]; a < head_[b + 1]; ++a) {
                  const core::Real xi = sx_[a], yi = sy_[a], zi = sz_[a];
                  for (std::size_t e = (c == b ? a + 1 : head_[c]); e < head_[c + 1]; ++e) {
                    const core::Real ddx = xi - sx_[e], ddy = yi - sy_[e], ddz = zi - sz_[e];
                    const core::Real r2 = ddx * ddx + ddy * ddy + ddz * ddz;
                    if (r2 < rc2) f(order_[a], order_[e], r2);
                  }
                }
              }
        }
  }

 private:
  std::size_t index(int bx, int by, int bz) const {
    return (static_cast<std::size_t>(bz) * nb_[1] + by) * nb_[0] + bx;
  }
  std::size_t bin_of(std::size_t i) const {
    const core::Real p[3] = {x_[i], y_[i], z_[i]};
    int b[3];
    for (int d = 0; d < 3; ++d)
      b[d] = std::clamp(static_cast<int>((p[d] - lo_[d]) / edge_[d]), 0, nb_[d] - 1);
    return index(b[0], b[1], b[2]);
  }
  const core::Real *x_, *y_, *z_;
  std::size_t n_;
  core::Real cutoff_;
  core::Vec3 lo_{}, edge_{};
  int nb_[3] = {1, 1, 1};
  std::vector<std::size_t> head_, bin_, order_;
  std::vector<core::Real> sx_, sy_, sz_;  // coordinates in bin order
};

}  // namespace biota::particles
