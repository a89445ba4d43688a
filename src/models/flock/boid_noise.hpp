#pragma once
/// \file boid_noise.hpp
/// \brief 1/f-type fluctuations of boid parameters from midpoint-displacement fBm (spec boids.md
/// 2.6, ambiguities 10 and 11): a static 2D field per parameter over the take-off grid, and a 1D
/// series in time per boid for the heading.
#include <cstdint>
#include <vector>

namespace biota::models::flock {

/// \brief Which fBm signal drives a fluctuation (spec ambiguity 10).
enum class FbmSignal {
  kPath,        ///< the fBm path (bridge form), spectrum ~ 1/f^(2H+1); 1/f as H -> 0
  kIncrements,  ///< its increments (fractional Gaussian noise), spectrum ~ 1/f^(2H-1); 1/f as H ->
                ///< 1
};

/// \brief One block of 2^levels samples of a zero-mean, unit-variance fluctuation for boid `id`.
///
/// kPath: the midpoint_fbm_1d path X minus its chord t X(1) (an fBm bridge), so every block starts
/// and ends at 0, so consecutive blocks join continuously; each block is scaled to unit mean
/// square (midpoint displacement is only approximately fBm, so no closed-form variance is exact).
/// kIncrements: X(t_{i+1}) - X(t_i) scaled by 2^{levels H} (unit variance).
/// Stream: midpoint_fbm_1d(seed, series_id = id * 2^20 + block), so a block depends only on
/// (seed, id, block) and any rank can rebuild it after a migration.
/// \throws std::invalid_argument unless 0 < H < 1, 1 <= levels <= 20 and block < 2^20.
std::vector<double> heading_noise_block(int levels, double hurst, FbmSignal signal,
                                        std::uint64_t seed, std::uint64_t id, std::uint64_t block);

/// \brief A 2D fBm field (midpoint_fbm_2d) on a (2^levels + 1)² grid, shifted and scaled to zero
/// mean and unit variance over the grid (sums in index order, so identical on every rank).
/// The paper places boids on a square grid and fluctuates their parameters with the 2D midpoint
/// displacement (spec 2.6); boid k takes grid point (k mod G, k / G), G = 2^levels + 1.
std::vector<double> normalized_fbm_field(int levels, double hurst, std::uint64_t seed,
                                         std::uint64_t field_id);

}  // namespace biota::models::flock
