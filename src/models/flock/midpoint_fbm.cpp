/// \file midpoint_fbm.cpp
/// \brief Midpoint-displacement fBm generators.
#include "models/flock/midpoint_fbm.hpp"

#include <cmath>
#include <stdexcept>

#include "core/rng.hpp"

namespace biota::models::flock {

std::vector<double> midpoint_fbm_1d(int levels, double hurst, double sigma, std::uint64_t seed,
                                    std::uint64_t series_id) {
  if (!(hurst > 0 && hurst < 1) || levels < 0 || levels > 30)
    throw std::invalid_argument("midpoint_fbm_1d: need 0 < H < 1 and 0 <= levels <= 30");
  core::Rng rng(seed, series_id, 0, core::RngPurpose::kFbm);
  const std::size_t n = std::size_t{1} << levels;
  std::vector<double> x(n + 1);
  x[0] = 0.0;
  x[n] = sigma * rng.normal();
  const double factor = std::sqrt(1.0 - std::pow(2.0, 2.0 * hurst - 2.0));
  std::size_t step = n;
  for (int stage = 1; stage <= levels; ++stage) {
    const std::size_t half = step / 2;
    const double delta = sigma * factor * std::pow(2.0, -hurst * stage);  // eq. 5.1, standard
    for (std::size_t i = half; i < n; i += step)
      x[i] = 0.5 * (x[i - half] + x[i + half]) + delta * rng.normal();
    step = half;
  }
  return x;
}

std::vector<double> midpoint_fbm_2d(int levels, double hurst, double sigma, std::uint64_t seed,
                                    std::uint64_t field_id) {
  if (!(hurst > 0 && hurst < 1) || levels < 0 || levels > 15)
    throw std::invalid_argument("midpoint_fbm_2d: need 0 < H < 1 and 0 <= levels <= 15");
  core::Rng rng(seed, field_id, 1, core::RngPurpose::kFbm);
  const int n = 1 << levels, w = n + 1;
  std::vector<double> f(static_cast<std::size_t>(w) * w, 0.0);
  auto at = [&](int i, int j) -> double& { return f[i + static_cast<std::size_t>(w) * j]; };
  double delta = sigma;
  at(0, 0) = delta * rng.normal();
  at(n, 0) = delta * rng.normal();
  at(0, n) = delta * rng.normal();
  at(n, n) = delta * rng.normal();
  const double shrink = std::pow(0.5, 0.5 * hurst);
  // Mean of the axis neighbours that exist (3 on the border) plus a displacement.
  auto edge = [&](int i, int j, int d) {
    double s = 0;
    int c = 0;
    if (i - d >= 0) s += at(i - d, j), ++c;
    if (i + d <= n) s += at(i + d, j), ++c;
    if (j - d >= 0) s += at(i, j - d), ++c;
    if (j + d <= n) s += at(i, j + d), ++c;
    at(i, j) = s / c + delta * rng.normal();
  };
  for (int step = n; step > 1; step /= 2) {
    const int d = step / 2;
    delta *= shrink;  // square centres: spacing step -> step / sqrt(2)
    for (int j = d; j < n; j += step)
      for (int i = d; i < n; i += step)
        at(i, j) =
            0.25 * (at(i - d, j - d) + at(i + d, j - d) + at(i - d, j + d) + at(i + d, j + d)) +
            delta * rng.normal();
    delta *= shrink;  // edge midpoints: spacing step / sqrt(2) -> step / 2
    for (int j = 0; j <= n; j += d)
      for (int i = ((j / d) % 2 == 0) ? d : 0; i <= n; i += step) edge(i, j, d);
  }
  return f;
}

}  // namespace biota::models::flock
