/// \file boid_noise.cpp
/// \brief Heading noise (one long fBm path per boid) and the 2D parameter fields.
#include "models/flock/boid_noise.hpp"

#include <cmath>
#include <stdexcept>

#include "models/flock/midpoint_fbm.hpp"

namespace biota::models::flock {

std::vector<double> heading_noise_block(int levels, double hurst, FbmSignal signal,
                                        std::uint64_t seed, std::uint64_t id, std::uint64_t block) {
  constexpr int kH = FbmSeries::kHorizonLevels;
  if (levels < 1 || levels > 20) throw std::invalid_argument("heading noise: levels not in 1..20");
  if (block >= (std::uint64_t{1} << (kH - levels)))
    throw std::invalid_argument("heading noise: frame beyond the 2^40-frame horizon");
  const std::size_t n = std::size_t{1} << levels;
  std::vector<double> out(n);
  if (signal == FbmSignal::kIncrements) {
    // sigma = 2^(40 H): Var[X(t + 1) - X(t)] = 1.
    const auto x = FbmSeries(hurst, std::pow(2.0, kH * hurst), seed, id).block(levels, block);
    for (std::size_t i = 0; i < n; ++i) out[i] = x[i + 1] - x[i];
    return out;
  }
  // sigma = 2^((40 - levels) H): the RMS change over one block of 2^levels frames is 1.
  const auto x =
      FbmSeries(hurst, std::pow(2.0, (kH - levels) * hurst), seed, id).block(levels, block);
  for (std::size_t i = 0; i < n; ++i) out[i] = x[i];
  return out;
}

std::vector<double> normalized_fbm_field(int levels, double hurst, std::uint64_t seed,
                                         std::uint64_t field_id) {
  auto f = midpoint_fbm_2d(levels, hurst, 1.0, seed, field_id);
  double mean = 0;
  for (double v : f) mean += v;
  mean /= double(f.size());
  double var = 0;
  for (double v : f) var += (v - mean) * (v - mean);
  var /= double(f.size());
  const double inv = var > 0 ? 1 / std::sqrt(var) : 1.0;
  for (double& v : f) v = (v - mean) * inv;
  return f;
}

}  // namespace biota::models::flock
