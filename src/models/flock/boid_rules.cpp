#include "models/flock/boid_rules.hpp"

#include <cmath>
#include <stdexcept>

#include "models/flock/boid_noise.hpp"
#include "models/flock/midpoint_fbm.hpp"

namespace biota::models::flock {

double polarisation(std::span<const Vec3> velocities) {
  Vec3 sum{};
  std::size_t n = 0;
  for (const Vec3& v : velocities) {
    const Real s = core::norm(v);
    if (s == 0) continue;
    sum += v / s;
    ++n;
  }
  return n == 0 ? 0.0 : core::norm(sum) / double(n);
}

std::vector<double> heading_noise_block(int levels, double hurst, FbmSignal signal,
                                        std::uint64_t seed, std::uint64_t id, std::uint64_t block) {
  if (levels < 1 || levels > 20) throw std::invalid_argument("heading noise: levels not in 1..20");
  if (block >= (1u << 20)) throw std::invalid_argument("heading noise: block >= 2^20");
  const std::size_t n = std::size_t{1} << levels;
  const auto x = midpoint_fbm_1d(levels, hurst, 1.0, seed, (id << 20) | block);
  std::vector<double> out(n);
  if (signal == FbmSignal::kIncrements) {
    const double scale = std::pow(2.0, levels * hurst);
    for (std::size_t i = 0; i < n; ++i) out[i] = (x[i + 1] - x[i]) * scale;
    return out;
  }
  // Bridge B(t) = X(t) - t X(1): zero at both ends. Midpoint displacement is only approximately
  // fBm (its variance at t is not exactly t^{2H}), so the block is scaled to unit mean square by
  // its own RMS: deterministic, and the amplitude key then means what it says.
  double ms = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = double(i) / double(n);
    out[i] = x[i] - t * x[n];
    ms += out[i] * out[i];
  }
  ms /= double(n);
  const double inv = ms > 0 ? 1 / std::sqrt(ms) : 1.0;
  for (double& v : out) v *= inv;
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
