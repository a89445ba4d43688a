/// \file power_law_fit.cpp
/// \brief Power-law fits for avalanche statistics.
#include "models/flock/power_law_fit.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace biota::models::flock {

namespace {
struct Line {
  double slope, slope_error;
};

// Ordinary least squares y = a + b x with the textbook standard error of b.
Line least_squares(const std::vector<double>& x, const std::vector<double>& y) {
  const double n = static_cast<double>(x.size());
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    mx += x[i];
    my += y[i];
  }
  mx /= n;
  my /= n;
  double sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (y[i] - my);
  }
  const double b = sxy / sxx;
  double rss = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double e = y[i] - my - b * (x[i] - mx);
    rss += e * e;
  }
  const double err = x.size() > 2 ? std::sqrt(rss / (n - 2) / sxx) : 0.0;
  return {b, err};
}
}  // namespace

PowerLawFit fit_power_law_log_binned(std::span<const std::int64_t> histogram, std::int64_t s_min,
                                     std::int64_t s_max, int bins_per_decade) {
  if (s_min < 1 || s_max <= s_min || bins_per_decade < 1)
    throw std::invalid_argument("fit_power_law_log_binned: need 1 <= s_min < s_max");
  s_max = std::min<std::int64_t>(s_max, static_cast<std::int64_t>(histogram.size()) - 1);
  std::vector<double> lx, ly;
  PowerLawFit fit;
  const double ratio = std::pow(10.0, 1.0 / bins_per_decade);
  double edge = static_cast<double>(s_min);
  std::int64_t first = s_min;
  while (first <= s_max) {
    edge *= ratio;
    // integers in [first, last]; at least one per bin so small s is not split into empty bins
    const std::int64_t last = std::min<std::int64_t>(
        s_max, std::max<std::int64_t>(first, std::llround(std::ceil(edge)) - 1));
    std::int64_t count = 0;
    for (std::int64_t s = first; s <= last; ++s) count += histogram[s];
    if (count > 0) {
      fit.samples += count;
      lx.push_back(0.5 *
                   (std::log(static_cast<double>(first)) + std::log(static_cast<double>(last))));
      ly.push_back(std::log(static_cast<double>(count) / static_cast<double>(last - first + 1)));
    }
    first = last + 1;
  }
  if (lx.size() < 3)
    throw std::invalid_argument("fit_power_law_log_binned: fewer than 3 non-empty bins");
  const Line l = least_squares(lx, ly);
  fit.tau = -l.slope;
  fit.tau_error = l.slope_error;
  fit.points = static_cast<int>(lx.size());
  return fit;
}

PowerLawFit fit_power_law_mle(std::span<const std::int64_t> histogram, std::int64_t s_min,
                              std::int64_t s_max) {
  if (s_min < 1 || s_max <= s_min)
    throw std::invalid_argument("fit_power_law_mle: need 1 <= s_min < s_max");
  s_max = std::min<std::int64_t>(s_max, static_cast<std::int64_t>(histogram.size()) - 1);
  PowerLawFit fit;
  double sum_log = 0;
  for (std::int64_t s = s_min; s <= s_max; ++s) {
    fit.samples += histogram[s];
    sum_log += static_cast<double>(histogram[s]) * std::log(static_cast<double>(s));
  }
  if (fit.samples == 0) throw std::invalid_argument("fit_power_law_mle: empty window");
  const double target = sum_log / static_cast<double>(fit.samples);
  // Model moments of ln s; weights are normalised by s_min^-τ to avoid underflow at large τ.
  auto moments = [&](double tau, double& mean, double& var) {
    double z = 0, m1 = 0, m2 = 0;
    const double l0 = std::log(static_cast<double>(s_min));
    for (std::int64_t s = s_min; s <= s_max; ++s) {
      const double ls = std::log(static_cast<double>(s));
      const double w = std::exp(-tau * (ls - l0));
      z += w;
      m1 += w * ls;
      m2 += w * ls * ls;
    }
    mean = m1 / z;
    var = m2 / z - mean * mean;
  };
  double lo = -5, hi = 10, mean = 0, var = 0;  // ⟨ln s⟩_τ decreases with τ
  for (int it = 0; it < 60; ++it) {
    const double mid = 0.5 * (lo + hi);
    moments(mid, mean, var);
    (mean > target ? lo : hi) = mid;
  }
  fit.tau = 0.5 * (lo + hi);
  moments(fit.tau, mean, var);
  fit.tau_error = 1.0 / std::sqrt(static_cast<double>(fit.samples) * var);
  return fit;
}

double zipf_rank_size_slope(std::span<const std::int64_t> histogram, std::int64_t r_min,
                            std::int64_t r_max) {
  std::int64_t nonzero = 0;
  for (std::size_t s = 1; s < histogram.size(); ++s) nonzero += histogram[s];
  if (r_min < 1 || r_max <= r_min || r_max > nonzero)
    throw std::invalid_argument("zipf_rank_size_slope: need 1 <= r_min < r_max <= #(s >= 1)");
  constexpr int kPoints = 20;
  std::vector<double> lr, ls;
  for (int k = 0; k < kPoints; ++k) {
    const auto r = static_cast<std::int64_t>(std::llround(
        static_cast<double>(r_min) *
        std::pow(static_cast<double>(r_max) / static_cast<double>(r_min), k / (kPoints - 1.0))));
    // size of rank r: the largest s with #(sizes >= s) >= r
    std::int64_t above = 0, s = static_cast<std::int64_t>(histogram.size()) - 1;
    for (; s >= 1; --s) {
      above += histogram[s];
      if (above >= r) break;
    }
    lr.push_back(std::log(static_cast<double>(r)));
    ls.push_back(std::log(static_cast<double>(s)));
  }
  return -least_squares(lr, ls).slope;
}

}  // namespace biota::models::flock
