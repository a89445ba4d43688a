/// \file midpoint_fbm.cpp
/// \brief Midpoint-displacement fBm generators.
#include "models/flock/midpoint_fbm.hpp"

#include <algorithm>
#include <array>
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

FbmSeries::FbmSeries(double hurst, double sigma, std::uint64_t seed, std::uint64_t series_id,
                     int horizon_levels)
    : hurst_(hurst),
      sigma_(sigma),
      factor_(std::sqrt(1.0 - std::pow(2.0, 2.0 * hurst - 2.0))),
      seed_(seed),
      id_(series_id),
      horizon_(horizon_levels) {
  if (!(hurst > 0 && hurst < 1) || horizon_levels < 1 || horizon_levels > 62)
    throw std::invalid_argument("FbmSeries: need 0 < H < 1 and 1 <= horizon_levels <= 62");
}

double FbmSeries::draw(std::uint64_t t) const {
  return core::Rng(seed_, id_, t, core::RngPurpose::kFbmSeries).normal();
}

double FbmSeries::delta(int stage) const {
  return sigma_ * factor_ * std::pow(2.0, -hurst_ * stage);  // eq. 5.1, standard form
}

std::vector<double> FbmSeries::block(int levels, std::uint64_t b) const {
  if (levels < 0 || levels > horizon_ || b >= (std::uint64_t{1} << (horizon_ - levels)))
    throw std::invalid_argument("FbmSeries::block: block beyond the horizon");
  // Descend from [0, 2^horizon] to the block's interval, creating only the midpoints on the way.
  std::uint64_t lo = 0, hi = std::uint64_t{1} << horizon_;
  double x_lo = 0.0, x_hi = sigma_ * draw(hi);
  const std::uint64_t left = b << levels;
  for (int stage = 1; stage <= horizon_ - levels; ++stage) {
    const std::uint64_t mid = lo + (hi - lo) / 2;
    const double x_mid = 0.5 * (x_lo + x_hi) + delta(stage) * draw(mid);
    if (left >= mid)
      lo = mid, x_lo = x_mid;
    else
      hi = mid, x_hi = x_mid;
  }
  // Refine inside the block: the same stages as midpoint_fbm_1d, node draws by position.
  const std::size_t n = std::size_t{1} << levels;
  std::vector<double> x(n + 1);
  x[0] = x_lo;
  x[n] = x_hi;
  std::size_t step = n;
  for (int stage = horizon_ - levels + 1; stage <= horizon_; ++stage) {
    const std::size_t half = step / 2;
    for (std::size_t i = half; i < n; i += step)
      x[i] = 0.5 * (x[i - half] + x[i + half]) + delta(stage) * draw(lo + i);
    step = half;
  }
  return x;
}

double FbmSeries::at(std::uint64_t t) const {
  if (t == (std::uint64_t{1} << horizon_)) return block(0, t - 1)[1];
  return block(0, t)[0];
}

namespace {
// Variance of Σ w_k X(p_k) for weights summing to zero, from the fBm variogram
// V(r) = σ² r^(2H): Var = -1/2 Σ_kl w_k w_l V(|p_k - p_l|).
double combination_variance(const std::vector<std::array<double, 2>>& p,
                            const std::vector<double>& w, double hurst, double sigma2) {
  double v = 0;
  for (std::size_t k = 0; k < p.size(); ++k)
    for (std::size_t l = 0; l < p.size(); ++l) {
      const double r = std::hypot(p[k][0] - p[l][0], p[k][1] - p[l][1]);
      v -= 0.5 * w[k] * w[l] * sigma2 * std::pow(r, 2 * hurst);
    }
  return v;
}

// Displacement variance for a new point at the origin set to the mean of `nb` (all at the same
// distance t) plus δ G: δ² = V(t) - mean_j Var[mean - X_j], so that the new point has, on average
// over its parents, the fBm variogram to them. The 2D analogue of the factor (1 - 2^(2H-2)) of
// eq. 5.1, which is exactly this formula for two parents on a line.
double displacement_variance(const std::vector<std::array<double, 2>>& nb, double hurst,
                             double sigma2) {
  const std::size_t k = nb.size();
  const double t = std::hypot(nb[0][0], nb[0][1]);
  double mean_var = 0;
  for (std::size_t j = 0; j < k; ++j) {
    std::vector<double> w(k, 1.0 / static_cast<double>(k));
    w[j] -= 1.0;
    mean_var += combination_variance(nb, w, hurst, sigma2);
  }
  return std::max(0.0, sigma2 * std::pow(t, 2 * hurst) - mean_var / static_cast<double>(k));
}
}  // namespace

std::vector<double> midpoint_fbm_2d(int levels, double hurst, double sigma, std::uint64_t seed,
                                    std::uint64_t field_id) {
  if (!(hurst > 0 && hurst < 1) || levels < 0 || levels > 15)
    throw std::invalid_argument("midpoint_fbm_2d: need 0 < H < 1 and 0 <= levels <= 15");
  core::Rng rng(seed, field_id, 1, core::RngPurpose::kFbm);
  const int n = 1 << levels, w = n + 1;
  const double s2 = sigma * sigma;
  std::vector<double> f(static_cast<std::size_t>(w) * w, 0.0);
  auto at = [&](int i, int j) -> double& { return f[i + static_cast<std::size_t>(w) * j]; };
  {
    // Corners: X(0,0) = 0 (as X(0) = 0 in 1D) and the other three drawn jointly with the fBm
    // covariance C_kl = (V(p_k) + V(p_l) - V(|p_k - p_l|)) / 2 (Cholesky), unit = grid side.
    const double p[3][2] = {{1, 0}, {0, 1}, {1, 1}};
    auto v = [&](double x, double y) { return s2 * std::pow(std::hypot(x, y), 2 * hurst); };
    double c[3][3], l[3][3] = {};
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        c[a][b] = 0.5 * (v(p[a][0], p[a][1]) + v(p[b][0], p[b][1]) -
                         v(p[a][0] - p[b][0], p[a][1] - p[b][1]));
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b <= a; ++b) {
        double sum = c[a][b];
        for (int k = 0; k < b; ++k) sum -= l[a][k] * l[b][k];
        l[a][b] = a == b ? std::sqrt(sum) : sum / l[b][b];
      }
    const double g[3] = {rng.normal(), rng.normal(), rng.normal()};
    double x[3];
    for (int a = 0; a < 3; ++a) x[a] = l[a][0] * g[0] + l[a][1] * g[1] + l[a][2] * g[2];
    at(n, 0) = x[0];
    at(0, n) = x[1];
    at(n, n) = x[2];
  }
  for (int step = n; step > 1; step /= 2) {
    const int d = step / 2;
    const double u = static_cast<double>(d) / n;  // half spacing in units of the grid side
    // Square centres from their 4 diagonal corners.
    const double dc =
        std::sqrt(displacement_variance({{u, u}, {-u, u}, {u, -u}, {-u, -u}}, hurst, s2));
    for (int j = d; j < n; j += step)
      for (int i = d; i < n; i += step)
        at(i, j) =
            0.25 * (at(i - d, j - d) + at(i + d, j - d) + at(i - d, j + d) + at(i + d, j + d)) +
            dc * rng.normal();
    // Edge midpoints from their 4 axis neighbours, or 3 on the border of the grid.
    const double de =
        std::sqrt(displacement_variance({{u, 0}, {0, u}, {-u, 0}, {0, -u}}, hurst, s2));
    const double db = std::sqrt(displacement_variance({{u, 0}, {-u, 0}, {0, u}}, hurst, s2));
    for (int j = 0; j <= n; j += d)
      for (int i = ((j / d) % 2 == 0) ? d : 0; i <= n; i += step) {
        double sum = 0;
        int cnt = 0;
        if (i - d >= 0) sum += at(i - d, j), ++cnt;
        if (i + d <= n) sum += at(i + d, j), ++cnt;
        if (j - d >= 0) sum += at(i, j - d), ++cnt;
        if (j + d <= n) sum += at(i, j + d), ++cnt;
        at(i, j) = sum / cnt + (cnt == 4 ? de : db) * rng.normal();
      }
  }
  return f;
}

}  // namespace biota::models::flock
