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

/// \brief Frames [b 2^levels, (b + 1) 2^levels) of the heading-noise series of boid `id`.
///
/// The series is one FbmSeries path per boid (seed, series id = boid id) over 2^40 frames, cut
/// into blocks only for caching: consecutive blocks join into one fBm path (an earlier version
/// drew an independent fBm bridge per block, reset to 0 every 2^levels frames, which removed all
/// power below the block frequency). kPath: X(t), scaled so the RMS change over 2^levels frames is
/// 1 (X(0) = 0; spectrum ~ 1/f^(2H+1) over the whole run). kIncrements: X(t + 1) - X(t) scaled to
/// unit variance (spectrum ~ 1/f^(2H-1)). Depends only on (seed, id, frame): any rank can rebuild
/// it after a migration or a restart.
/// \throws std::invalid_argument unless 0 < H < 1, 1 <= levels <= 20 and the block lies within
/// the 2^40-frame horizon.
std::vector<double> heading_noise_block(int levels, double hurst, FbmSignal signal,
                                        std::uint64_t seed, std::uint64_t id, std::uint64_t block);

/// \brief A 2D fBm field (midpoint_fbm_2d) on a (2^levels + 1)² grid, shifted and scaled to zero
/// mean and unit variance over the grid (sums in index order, so identical on every rank).
/// The paper places boids on a square grid and fluctuates their parameters with the 2D midpoint
/// displacement (spec 2.6); boid k takes grid point (k mod G, k / G), G = 2^levels + 1.
std::vector<double> normalized_fbm_field(int levels, double hurst, std::uint64_t seed,
                                         std::uint64_t field_id);

}  // namespace biota::models::flock
