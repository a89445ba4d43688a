#pragma once
/// \file bench_stats.hpp
/// \brief Statistics the benchmarks report over their rounds.
#include <algorithm>
#include <vector>

namespace biota::app {

/// \brief Median of `v` (the mean of the middle two for an even count); `v` must not be empty.
inline double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

}  // namespace biota::app
