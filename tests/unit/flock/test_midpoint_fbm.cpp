/// \file test_midpoint_fbm.cpp
/// \brief Midpoint-displacement fBm: stage variances (eq. 5.1), spectrum, increment scaling.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>
#include <vector>

#include "models/flock/boid_noise.hpp"
#include "models/flock/midpoint_fbm.hpp"

using biota::models::flock::midpoint_fbm_1d;
using biota::models::flock::midpoint_fbm_2d;

namespace {

// In-place iterative radix-2 FFT (size a power of two).
void fft(std::vector<std::complex<double>>& a) {
  const std::size_t n = a.size();
  for (std::size_t i = 1, j = 0; i < n; ++i) {
    std::size_t bit = n >> 1;
    for (; j & bit; bit >>= 1) j ^= bit;
    j ^= bit;
    if (i < j) std::swap(a[i], a[j]);
  }
  for (std::size_t len = 2; len <= n; len <<= 1) {
    const double ang = -2 * std::numbers::pi / static_cast<double>(len);
    const std::complex<double> wl(std::cos(ang), std::sin(ang));
    for (std::size_t i = 0; i < n; i += len) {
      std::complex<double> w(1);
      for (std::size_t k = 0; k < len / 2; ++k, w *= wl) {
        const auto u = a[i + k], v = a[i + k + len / 2] * w;
        a[i + k] = u + v;
        a[i + k + len / 2] = u - v;
      }
    }
  }
}

double slope(const std::vector<double>& x, const std::vector<double>& y) {
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < x.size(); ++i) mx += x[i], my += y[i];
  mx /= static_cast<double>(x.size());
  my /= static_cast<double>(x.size());
  double sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (y[i] - my);
  }
  return sxy / sxx;
}

// Average periodogram slope of `series` fBm paths of 2^levels + 1 points. The line through the
// end points is subtracted first ("end matching", Peitgen & Saupe) so that the periodic FFT sees no
// jump: a jump would leak as 1/f^2 and cap any steeper spectrum at slope -2. The fit uses
// logarithmic frequency bins over f in [2^-12, 2^-4] cycles per sample: away from the lowest
// frequencies (few modes, end-matching distortion) and from the highest (discreteness of the
// finest stage).
template <class Gen>
double periodogram_slope_of(Gen&& gen, int levels, int series, std::size_t k_lo_shift = 12) {
  const std::size_t n = std::size_t{1} << levels;
  std::vector<double> power(n / 2 + 1, 0.0);
  for (int sid = 0; sid < series; ++sid) {
    const std::vector<double> x = gen(static_cast<std::uint64_t>(sid));
    std::vector<std::complex<double>> a(n);
    for (std::size_t i = 0; i < n; ++i)
      a[i] = x[i] - (x[0] + (x[n] - x[0]) * static_cast<double>(i) / static_cast<double>(n));
    fft(a);
    for (std::size_t k = 1; k <= n / 2; ++k) power[k] += std::norm(a[k]);
  }
  std::vector<double> lf, lp;
  const std::size_t k_lo = std::max<std::size_t>(n >> k_lo_shift, 1), k_hi = n >> 4;
  for (std::size_t k0 = k_lo; k0 < k_hi; k0 *= 2) {  // 4 bins per octave
    for (int q = 0; q < 4; ++q) {
      const auto a = static_cast<std::size_t>(k0 * std::pow(2.0, q / 4.0));
      const auto b = static_cast<std::size_t>(k0 * std::pow(2.0, (q + 1) / 4.0));
      double p = 0, lk = 0;
      for (std::size_t k = a; k < b; ++k) p += power[k], lk += std::log(static_cast<double>(k));
      lf.push_back(lk / static_cast<double>(b - a));
      lp.push_back(std::log(p / static_cast<double>(b - a)));
    }
  }
  return slope(lf, lp);
}

double periodogram_slope(double h, int levels, int series) {
  return periodogram_slope_of(
      [&](std::uint64_t sid) { return midpoint_fbm_1d(levels, h, 1.0, 99, sid); }, levels, series);
}

// The heading noise of one boid over a whole run of 2^levels frames, as the scenario reads it:
// block after block of 2^block_levels frames (plus the first frame of the next block).
std::vector<double> heading_series(double h, int levels, int block_levels, std::uint64_t id) {
  using namespace biota::models::flock;
  std::vector<double> x;
  for (std::uint64_t b = 0; x.size() <= (std::size_t{1} << levels); ++b) {
    const auto blk = heading_noise_block(block_levels, h, FbmSignal::kPath, 99, id, b);
    x.insert(x.end(), blk.begin(), blk.end());
  }
  x.resize((std::size_t{1} << levels) + 1);
  return x;
}

}  // namespace

TEST(MidpointFbm, StageDisplacementVarianceIsEq51StandardForm) {
  // Residual of each new midpoint about the mean of its parents, per stage n, against
  // Δ_n² = σ² (1 - 2^(2H-2)) / (2^n)^(2H). Tolerance: 5 standard errors of a variance estimate
  // from m normal samples, 5 σ² sqrt(2/m).
  const int levels = 12, series = 64;
  const double h = 0.3, sigma = 2.0;
  std::vector<double> sum2(levels + 1, 0.0);
  std::vector<long> count(levels + 1, 0);
  for (int sid = 0; sid < series; ++sid) {
    const auto x = midpoint_fbm_1d(levels, h, sigma, 5, static_cast<std::uint64_t>(sid));
    std::size_t step = std::size_t{1} << levels;
    for (int stage = 1; stage <= levels; ++stage) {
      const std::size_t half = step / 2;
      for (std::size_t i = half; i + half < x.size(); i += step) {
        const double r = x[i] - 0.5 * (x[i - half] + x[i + half]);
        sum2[stage] += r * r;
        ++count[stage];
      }
      step = half;
    }
  }
  for (int stage = 3; stage <= levels; ++stage) {
    const double expect =
        sigma * sigma * (1 - std::pow(2.0, 2 * h - 2)) / std::pow(std::pow(2.0, stage), 2 * h);
    const double m = static_cast<double>(count[stage]);
    EXPECT_NEAR(sum2[stage] / m, expect, 5 * expect * std::sqrt(2 / m)) << "stage " << stage;
  }
}

TEST(MidpointFbm, PeriodogramSlopeIsMinus2HPlus1) {
  // 16 series of 2^16 + 1 points per H; tolerance ±0.15 on the slope -(2H + 1).
  for (double h : {0.3, 0.5, 0.8}) {
    const double s = periodogram_slope(h, 16, 16);
    std::printf("[ fbm ] H=%.1f periodogram slope %.4f, expected %.4f\n", h, s, -(2 * h + 1));
    EXPECT_NEAR(s, -(2 * h + 1), 0.15) << "H = " << h;
  }
}

TEST(MidpointFbm, IncrementVarianceScalesAsLagTo2H) {
  // Var[X(t + τ) - X(t)] over all t and 16 series for 16 log-spaced lags τ in [1, 1024] (dyadic and
  // non-dyadic). Midpoint displacement has non-stationary increments for H != 1/2 (the variance
  // depends on the position of t in the dyadic tree), so the averaged law is only approximately a
  // power; ±0.05 on 2H is what the method meets, and H = 1/2 (exact Brownian motion) is held to
  // ±0.02.
  const int levels = 16, series = 16;
  for (double h : {0.3, 0.5, 0.8}) {
    std::vector<double> lags, lvar;
    std::vector<std::vector<double>> paths;
    for (int sid = 0; sid < series; ++sid)
      paths.push_back(midpoint_fbm_1d(levels, h, 1.0, 7, static_cast<std::uint64_t>(sid)));
    for (int j = 0; j <= 15; ++j) {
      const auto tau = static_cast<std::size_t>(std::llround(std::pow(2.0, j * 10.0 / 15.0)));
      double s2 = 0;
      long m = 0;
      for (const auto& x : paths)
        for (std::size_t t = 0; t + tau < x.size(); ++t, ++m)
          s2 += (x[t + tau] - x[t]) * (x[t + tau] - x[t]);
      lags.push_back(std::log(static_cast<double>(tau)));
      lvar.push_back(std::log(s2 / static_cast<double>(m)));
    }
    const double e = slope(lags, lvar);
    std::printf("[ fbm ] H=%.1f increment-variance exponent %.4f, expected 2H = %.4f\n", h, e,
                2 * h);
    EXPECT_NEAR(e, 2 * h, h == 0.5 ? 0.02 : 0.05) << "H = " << h;
  }
}

TEST(MidpointFbm, Surface2DStructureFunctionScalesAsLagTo2H) {
  // Mean squared difference along x and y at lags 1..64 on 32 fields of 513². Diamond-square is
  // only approximately fBm in 2D even with the variogram-matched displacements: a point
  // interpolated from 4 parents is smoother than fBm (no Markov property in 2D, unlike H = 1/2 in
  // 1D), so the averaged structure function grows slower than r^(2H) over the sampled lags.
  // Measured exponents 0.600, 0.915, 1.504 for H = 0.3, 0.5, 0.8 (Peitgen & Saupe's original
  // constants gave 0.604, 0.913, 1.432). The test pins that characterisation: it checks the
  // exponent to ±0.12 of 2H and that it is monotonic in H, which is what the boid parameters need.
  const int levels = 9, w = (1 << levels) + 1;
  double previous = 0;
  for (double h : {0.3, 0.5, 0.8}) {
    std::vector<double> lags, lvar;
    std::vector<std::vector<double>> fields;
    for (int f = 0; f < 32; ++f) fields.push_back(midpoint_fbm_2d(levels, h, 1.0, 3, f));
    for (int r = 1; r <= 64; r *= 2) {
      double s2 = 0;
      long m = 0;
      for (const auto& z : fields)
        for (int j = 0; j + r < w; ++j)
          for (int i = 0; i + r < w; ++i, m += 2) {
            const double dx = z[i + r + w * j] - z[i + w * j],
                         dy = z[i + w * (j + r)] - z[i + w * j];
            s2 += dx * dx + dy * dy;
          }
      lags.push_back(std::log(static_cast<double>(r)));
      lvar.push_back(std::log(s2 / static_cast<double>(m)));
    }
    const double e = slope(lags, lvar);
    std::printf("[ fbm ] 2D H=%.1f structure-function exponent %.4f, expected 2H = %.4f\n", h, e,
                2 * h);
    EXPECT_NEAR(e, 2 * h, 0.12) << "H = " << h;
    EXPECT_GT(e, previous);
    previous = e;
  }
}

TEST(MidpointFbm, DeterministicPerSeedAndId) {
  EXPECT_EQ(midpoint_fbm_1d(10, 0.4, 1.0, 1, 2), midpoint_fbm_1d(10, 0.4, 1.0, 1, 2));
  EXPECT_NE(midpoint_fbm_1d(10, 0.4, 1.0, 1, 2), midpoint_fbm_1d(10, 0.4, 1.0, 1, 3));
  EXPECT_NE(midpoint_fbm_1d(10, 0.4, 1.0, 1, 2), midpoint_fbm_1d(10, 0.4, 1.0, 2, 2));
  EXPECT_EQ(midpoint_fbm_2d(6, 0.4, 1.0, 1, 2), midpoint_fbm_2d(6, 0.4, 1.0, 1, 2));
  EXPECT_NE(midpoint_fbm_2d(6, 0.4, 1.0, 1, 2), midpoint_fbm_2d(6, 0.4, 1.0, 1, 3));
  const auto x = midpoint_fbm_1d(8, 0.5, 1.0, 1, 2);
  EXPECT_EQ(x.size(), 257u);
  EXPECT_EQ(x[0], 0.0);
  EXPECT_EQ(midpoint_fbm_2d(4, 0.5, 1.0, 1, 2).size(), 17u * 17u);
  EXPECT_THROW(midpoint_fbm_1d(8, 1.0, 1.0, 1, 2), std::invalid_argument);
}

TEST(FbmSeries, HeadingNoiseSpectrumHoldsOverTheWholeRun) {
  // Issue 8: the heading noise was an fBm bridge reset every 2^levels frames, so the run's
  // spectrum was flat below the block frequency. Now blocks are pieces of one path: over a run of
  // 2^16 frames read in blocks of 2^8, the periodogram slope over f in [8/N, 1/16] (down to 8
  // cycles per run, 32x below the block frequency) is -(2H + 1). 16 boids, tolerance ±0.15 as
  // for midpoint_fbm_1d above.
  for (double h : {0.2, 0.5}) {
    const double s = periodogram_slope_of(
        [&](std::uint64_t id) { return heading_series(h, 16, 8, id); }, 16, 16, 13);
    std::printf(
        "[ fbm ] heading noise H=%.1f, 2^16 frames in blocks of 2^8: slope %.4f, "
        "expected %.4f\n",
        h, s, -(2 * h + 1));
    EXPECT_NEAR(s, -(2 * h + 1), 0.15) << "H = " << h;
  }
}

TEST(FbmSeries, BlocksAreRandomAccessAndRankIndependent) {
  using biota::models::flock::FbmSeries;
  const FbmSeries a(0.3, 1.0, 5, 42, 20), b(0.3, 1.0, 5, 42, 20);
  const auto fine = a.block(10, 7);    // frames 7168 .. 8192
  const auto coarse = b.block(12, 1);  // frames 4096 .. 8192: contains block (10, 7)
  for (std::size_t i = 0; i < fine.size(); ++i) EXPECT_EQ(fine[i], coarse[3072 + i]);
  EXPECT_EQ(a.at(0), 0.0);
  EXPECT_EQ(a.at(8192), coarse.back());
  EXPECT_THROW(a.block(10, 1024), std::invalid_argument);  // beyond 2^20
}
