#pragma once
/// \file power_law_fit.hpp
/// \brief Fits of the exponent τ of N(s) ~ s^-τ (spec boids.md 2.4, eqs. 3.3–3.4) to a histogram.
#include <cstdint>
#include <span>

namespace biota::models::flock {

/// \brief Result of a power-law fit over the window [s_min, s_max].
struct PowerLawFit {
  /// \brief Fitted exponent τ of P(s) ~ s^-τ (positive for a decaying law).
  double tau = 0;
  /// \brief One standard error of τ (regression error for the binned fit, Fisher information for
  /// the MLE). Statistical only: it does not include the bias from finite-size corrections.
  double tau_error = 0;
  /// \brief Avalanches with s in the window.
  std::int64_t samples = 0;
  /// \brief Points used by the regression (non-empty bins); 0 for the MLE.
  int points = 0;
};

/// \brief Least-squares slope of log P(s) against log s on logarithmic bins (eq. 3.4).
///
/// `histogram[s]` is the number of avalanches of size s. Bins start at s_min with `bins_per_decade`
/// bins per decade; each bin's density is its count divided by the number of integers it covers,
/// placed at the geometric mean of its first and last integer. Logarithmic bins give the sparse
/// tail the same weight per decade as the dense head, which is what a slope on a log-log plot (the
/// paper's method) means. Only the slope is fitted: eq. 3.4 omits the normalisation (erratum 5).
/// Empty bins are skipped; s_max is clipped to the histogram.
/// \throws std::invalid_argument if s_min < 1, s_max <= s_min or fewer than 3 bins are non-empty.
PowerLawFit fit_power_law_log_binned(std::span<const std::int64_t> histogram, std::int64_t s_min,
                                     std::int64_t s_max, int bins_per_decade = 5);

/// \brief Discrete maximum-likelihood τ of a power law truncated to [s_min, s_max].
///
/// Maximises Σ_s n_s log(s^-τ / Z(τ)), Z = Σ_{s=s_min}^{s_max} s^-τ, i.e. solves
/// ⟨ln s⟩_τ = mean of ln s over the data by bisection. Unbinned, so it has no binning choices and
/// the smallest variance; the explicit upper cut keeps the finite-size bump (s ~ L^3) out, which an
/// untruncated Clauset-style MLE with x_min alone would absorb into τ.
/// \throws std::invalid_argument if s_min < 1, s_max <= s_min or the window is empty.
PowerLawFit fit_power_law_mle(std::span<const std::int64_t> histogram, std::int64_t s_min,
                              std::int64_t s_max);

/// \brief Slope magnitude of the Zipf (rank–size) plot, log s(r) against log r, for r in
/// [r_min, r_max] on 20 log-spaced ranks.
///
/// For P(s) ~ s^-τ the rank–size law is s(r) ~ r^{-1/(τ-1)}; reported beside τ because the paper
/// calls its law Zipf's law and its printed 2.5554 may be this slope (spec ambiguity 4).
/// \throws std::invalid_argument if r_min < 1, r_max <= r_min or r_max exceeds the number of
/// avalanches with s >= 1.
double zipf_rank_size_slope(std::span<const std::int64_t> histogram, std::int64_t r_min,
                            std::int64_t r_max);

}  // namespace biota::models::flock
