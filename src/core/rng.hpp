#pragma once
/// \file rng.hpp
/// \brief Counter-based random numbers (Random123 Philox4x64-10).
///
/// A stream is fixed by (seed, global id, step, purpose): the same entity draws the same numbers on
/// any rank count and in any processing order, which is what makes stochastic models
/// decomposition-invariant. Never key a stream by rank.
#include <Random123/philox.h>

#include <cmath>
#include <cstdint>
#include <numbers>

namespace biota::core {

/// \brief Named purposes so that two uses of one entity at one step never share a stream.
enum class RngPurpose : std::uint64_t {
  kTest = 0,
  kGrowth = 1,
  kPlacement = 2,
  kInterference = 3,
  kLSystem = 4,
  kBoidInit = 10,
  kBoidNoise = 11,
  kSandpile = 12,
  kChaosGame = 13,
  kFbm = 14,
  kFbmSeries = 15,
  kMoss = 20,
  kPhoton = 21,
  kUser = 100,
};

/// \brief A stream of uniform draws for one (seed, id, step, purpose); cheap to create.
class Rng {
 public:
  Rng(std::uint64_t seed, std::uint64_t global_id, std::uint64_t step, RngPurpose purpose)
      : key_{{seed, global_id}}, ctr_{{step, static_cast<std::uint64_t>(purpose), 0, 0}} {}

  /// \brief Next raw 64-bit value.
  std::uint64_t next_u64() {
    if (used_ == 4) refill();
    return block_.v[used_++];
  }
  /// \brief Uniform double in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(next_u64() >> 11) * 0x1.0p-53; }
  /// \brief Uniform double in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// \brief Uniform integer in [lo, hi] (inclusive), unbiased by rejection.
  std::int64_t uniform_int(std::int64_t lo, std::int64_t hi) {
    const std::uint64_t span = static_cast<std::uint64_t>(hi - lo) + 1;
    if (span == 0) return static_cast<std::int64_t>(next_u64());
    const std::uint64_t limit = UINT64_MAX - UINT64_MAX % span;
    std::uint64_t r;
    do r = next_u64();
    while (r >= limit);
    return lo + static_cast<std::int64_t>(r % span);
  }
  /// \brief Bernoulli trial with probability p.
  bool bernoulli(double p) { return uniform() < p; }
  /// \brief Standard normal draw (Box-Muller, one value per call).
  double normal() {
    double u1 = uniform();
    while (u1 <= 0.0) u1 = uniform();
    const double u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
  }

 private:
  void refill() {
    block_ = r123::Philox4x64()(ctr_, key_);
    ++ctr_.v[2];
    used_ = 0;
  }
  r123::Philox4x64::key_type key_;
  r123::Philox4x64::ctr_type ctr_;
  r123::Philox4x64::ctr_type block_{};
  int used_ = 4;
};

}  // namespace biota::core
