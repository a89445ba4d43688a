#pragma once
/// \file cell_list.hpp
/// \brief O(N) neighbour search: particles binned into cubic cells of edge >= cutoff; pairs are
/// found by visiting the 27 surrounding bins (13 forward bins + own bin for a half list).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "core/compact_near.hpp"
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
    if (n > UINT32_MAX) throw std::length_error("CellList: more than 2^32 points");
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
  /// The pairs of bin b are those with its own later points and with the points of the 13 bins
  /// after it in (z, y, x) order. Those bins form five runs of consecutive slots in bin order:
  /// the rest of b's own x-row (b and the bin after it), and the x-rows (three bins each) at
  /// (y + 1, z), (y - 1..y + 1, z + 1). Each run is one contiguous range for
  /// core::compact_near (the accepted slots compacted in vector lanes, f called after). Every
  /// pair is oriented, and its r2 computed, as the bin-by-bin search computes it: i in the lower
  /// bin (or first in the same bin), r2 = ((xi - xj)^2 + (yi - yj)^2) + (zi - zj)^2; only the
  /// order of the calls differs.
  template <class F>
  void for_each_pair(F&& f) const {
    if (n_ == 0) return;
    const core::Real rc2 = cutoff_ * cutoff_;
    // Room for every slot of the ranges one point is tested against, plus one vector's overrun.
    std::vector<std::uint32_t> hit(n_ + 8);
    std::vector<core::Real> hit_r2(n_ + 8);
    for (int bz = 0; bz < nb_[2]; ++bz)
      for (int by = 0; by < nb_[1]; ++by)
        for (int bx = 0; bx < nb_[0]; ++bx) {
          const std::size_t b = index(bx, by, bz);
          if (head_[b] == head_[b + 1]) continue;  // sparse sets: most bins are empty
          const int x0 = std::max(bx - 1, 0), x1 = std::min(bx + 1, nb_[0] - 1);
          // The x-rows after b's own: [first, last) slot ranges.
          std::size_t row_first[4], row_last[4];
          int rows = 0;
          const auto add_row = [&](int cy, int cz) {
            if (cy < 0 || cy >= nb_[1] || cz >= nb_[2]) return;
            row_first[rows] = head_[index(x0, cy, cz)];
            row_last[rows] = head_[index(x1, cy, cz) + 1];
            rows += row_first[rows] < row_last[rows] ? 1 : 0;
          };
          add_row(by + 1, bz);
          for (int dy = -1; dy <= 1; ++dy) add_row(by + dy, bz + 1);
          const std::size_t own_last = head_[index(x1, by, bz) + 1];
          for (std::size_t a = head_[b]; a < head_[b + 1]; ++a) {
            const core::Vec3 p{sx_[a], sy_[a], sz_[a]};
            std::size_t n = near_in(p, a + 1, own_last, rc2, hit.data(), hit_r2.data());
            for (int r = 0; r < rows; ++r)
              n += near_in(p, row_first[r], row_last[r], rc2, hit.data() + n, hit_r2.data() + n);
            for (std::size_t h = 0; h < n; ++h) f(order_[a], order_[hit[h]], hit_r2[h]);
          }
        }
  }

 private:
  /// The slots k in [first, last) closer than sqrt(rc2) to p, in increasing k, to out (and
  /// their r2 to out_r2); returns their number. The differences are s_k - p, whose squares are
  /// those of p - s_k bit for bit.
  std::size_t near_in(const core::Vec3& p, std::size_t first, std::size_t last, core::Real rc2,
                      std::uint32_t* out, core::Real* out_r2) const {
    return core::compact_near(sx_.data() + first, sy_.data() + first, sz_.data() + first,
                              last - first, p, rc2, static_cast<std::uint32_t>(first), out, out_r2);
  }
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
