/// \file box_counting.cpp
/// \brief Box counting by sorting box keys.
#include "models/flock/box_counting.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace biota::models::flock {

BoxCounting box_counting_dimension(std::span<const core::Vec3> points, int dim, int level_min,
                                   int level_max) {
  if ((dim != 2 && dim != 3) || level_min < 0 || level_max <= level_min || level_max > 20 ||
      points.empty())
    throw std::invalid_argument("box_counting_dimension: bad dim, levels or empty point set");
  core::Vec3 lo = points[0], hi = points[0];
  for (const auto& p : points)
    for (int d = 0; d < dim; ++d) {
      lo[d] = std::min(lo[d], p[d]);
      hi[d] = std::max(hi[d], p[d]);
    }
  double side = 0;
  for (int d = 0; d < dim; ++d) side = std::max(side, hi[d] - lo[d]);
  if (!(side > 0)) throw std::invalid_argument("box_counting_dimension: all points coincide");

  BoxCounting out;
  std::vector<std::uint64_t> keys(points.size());
  std::vector<double> lx, ly;
  for (int k = level_min; k <= level_max; ++k) {
    const std::uint64_t m = std::uint64_t{1} << k;
    for (std::size_t i = 0; i < points.size(); ++i) {
      std::uint64_t key = 0;
      for (int d = 0; d < dim; ++d) {
        const auto c =
            static_cast<std::uint64_t>((points[i][d] - lo[d]) / side * static_cast<double>(m));
        key = (key << 21) | std::min(c, m - 1);  // 21 bits per axis: levels <= 20
      }
      keys[i] = key;
    }
    std::sort(keys.begin(), keys.end());
    const auto count = std::unique(keys.begin(), keys.end()) - keys.begin();
    out.levels.push_back(k);
    out.counts.push_back(count);
    lx.push_back(k * std::log(2.0));
    ly.push_back(std::log(static_cast<double>(count)));
  }
  const double n = static_cast<double>(lx.size());
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < lx.size(); ++i) mx += lx[i], my += ly[i];
  mx /= n;
  my /= n;
  double sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < lx.size(); ++i) {
    sxx += (lx[i] - mx) * (lx[i] - mx);
    sxy += (lx[i] - mx) * (ly[i] - my);
  }
  out.dimension = sxy / sxx;
  double rss = 0;
  for (std::size_t i = 0; i < lx.size(); ++i) {
    const double e = ly[i] - my - out.dimension * (lx[i] - mx);
    rss += e * e;
  }
  out.dimension_error = lx.size() > 2 ? std::sqrt(rss / (n - 2) / sxx) : 0.0;
  return out;
}

}  // namespace biota::models::flock
