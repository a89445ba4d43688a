#pragma once
/// \file midpoint_fbm.hpp
/// \brief Fractional Brownian motion by random midpoint displacement (spec boids.md 2.6, eq. 5.1).
///
/// Both generators draw from one core::Rng stream keyed by (seed, id, step, RngPurpose::kFbm), with
/// step 0 for 1D series and step 1 for 2D fields, so a series depends only on (seed, id) and never
/// on the rank that builds it. The path X has spectrum ~ 1/f^(2H+1); its increments (fractional
/// Gaussian noise) have ~ 1/f^(2H-1). Which one drives a boid parameter is the caller's choice
/// (spec ambiguity 10).
#include <cstdint>
#include <vector>

namespace biota::models::flock {

/// \brief 1D fBm path of 2^levels + 1 samples on t = i / 2^levels (Peitgen & Saupe MidPointFM1D).
///
/// X(0) = 0, X(1) = σ G; at stage n = 1..levels every new midpoint is the mean of its two
/// neighbours plus Δ_n G with Δ_n² = σ² (1 - 2^(2H-2)) / (2^n)^(2H) — eq. 5.1 in its standard
/// form; the printed (2n)^(2H) is erratum 9 and would not give fBm scaling. The correction factor
/// makes Var[X(t + 2^-n) - X(t)] = σ² 2^(-2Hn) for the pairs created at stage n. For H = 1/2 this
/// is exact Brownian motion; for H ≠ 1/2 the increments are only approximately stationary (a known
/// property of the method), which the tests quantify.
/// \throws std::invalid_argument unless 0 < H < 1 and 0 <= levels <= 30.
std::vector<double> midpoint_fbm_1d(int levels, double hurst, double sigma, std::uint64_t seed,
                                    std::uint64_t series_id);

/// \brief One 1D fBm path over a long horizon, t = 0 .. 2^horizon_levels (integer frames), by the
/// same midpoint displacement as midpoint_fbm_1d, evaluated lazily block by block.
///
/// The midpoint created at stage n is at an integer position t (odd multiple of 2^(horizon - n))
/// and its normal draw comes from core::Rng(seed, series_id, t, RngPurpose::kFbmSeries), so any
/// block can be built alone, on any rank, in O(horizon + 2^levels) draws, and consecutive blocks
/// are pieces of one path: no reset at block ends, so the spectrum ~ 1/f^(2H+1) holds over the
/// whole horizon (2^40 frames, more than run.steps allows), not only within a block.
/// X(0) = 0 and Var[X(t + s) - X(t)] ≈ sigma^2 (s / 2^horizon)^(2H). Shared by the flock's heading
/// noise and any model that needs a long 1/f-type series (keep the interface small).
class FbmSeries {
 public:
  static constexpr int kHorizonLevels = 40;
  /// \throws std::invalid_argument unless 0 < H < 1 and 1 <= horizon_levels <= 62.
  FbmSeries(double hurst, double sigma, std::uint64_t seed, std::uint64_t series_id,
            int horizon_levels = kHorizonLevels);
  /// \brief X(b 2^levels) .. X((b + 1) 2^levels): 2^levels + 1 samples of block b.
  /// \throws std::invalid_argument if the block is beyond the horizon or levels > horizon.
  std::vector<double> block(int levels, std::uint64_t b) const;
  /// \brief X(t) for one frame (a block of one interval).
  double at(std::uint64_t t) const;
  int horizon_levels() const { return horizon_; }
  double hurst() const { return hurst_; }

 private:
  double draw(std::uint64_t t) const;  // the standard normal of node t
  double delta(int stage) const;       // displacement standard deviation at stage n (eq. 5.1)
  double hurst_, sigma_, factor_;
  std::uint64_t seed_, id_;
  int horizon_;
};

/// \brief 2D fBm surface on a (2^levels + 1)² square grid by diamond-square midpoint displacement
/// (after Peitgen & Saupe MidPointFM2D, spec 2.6 "2D midpoint displacement (5.2)").
///
/// X(0,0) = 0 and the other three corners are drawn jointly with the exact fBm covariance
/// (variogram V(r) = σ² r^(2H), r in units of the grid side). Each stage has two half-steps that
/// shrink the spacing by √2: square centres from their 4 diagonal corners, then edge midpoints
/// from their 4 (3 on the border) axis neighbours, each plus δ G. Deviation from P&S, who scale δ
/// by 2^(-H/2) per half-step from δ = σ: here δ² = V(t) - mean_j Var[mean - X_j] (t = distance to
/// the parents), the 2D analogue of the factor (1 - 2^(2H-2)) in eq. 5.1, so each new point has
/// the fBm variogram to its parents on average. The field is still only approximately fBm (the
/// structure-function exponent is below 2H for large H, quantified in the tests), as with any
/// diamond-square scheme. Value (i, j) is at index i + (2^levels + 1) * j.
/// Use one field per boid parameter and coordinate (distinct field_id), spec ambiguity 11.
/// \throws std::invalid_argument unless 0 < H < 1 and 0 <= levels <= 15.
std::vector<double> midpoint_fbm_2d(int levels, double hurst, double sigma, std::uint64_t seed,
                                    std::uint64_t field_id);

}  // namespace biota::models::flock
