/// \file dhar.cpp
/// \brief Matrix-free CG solve of Δ x = 1 for dhar_mean_avalanche_size().
#include "models/flock/dhar.hpp"

#include <cmath>
#include <stdexcept>
#include <vector>

namespace biota::models::flock {

double dhar_mean_avalanche_size(int lx, int ly, int lz, int threshold) {
  if (lx < 1 || ly < 1 || lz < 1 || threshold < 5)
    throw std::invalid_argument("dhar_mean_avalanche_size: need extents >= 1 and threshold >= 5");
  const std::size_t n = static_cast<std::size_t>(lx) * ly * lz;
  const double diag = threshold + 1.0;
  auto apply = [&](const std::vector<double>& v, std::vector<double>& out) {
    for (int z = 0; z < lz; ++z)
      for (int y = 0; y < ly; ++y)
        for (int x = 0; x < lx; ++x) {
          const std::size_t i =
              x + static_cast<std::size_t>(lx) * (y + static_cast<std::size_t>(ly) * z);
          double s = diag * v[i];
          if (x > 0) s -= v[i - 1];
          if (x < lx - 1) s -= v[i + 1];
          if (y > 0) s -= v[i - lx];
          if (y < ly - 1) s -= v[i + lx];
          if (z > 0) s -= v[i - static_cast<std::size_t>(lx) * ly];
          if (z < lz - 1) s -= v[i + static_cast<std::size_t>(lx) * ly];
          out[i] = s;
        }
  };
  std::vector<double> x(n, 0.0), r(n, 1.0), p(n, 1.0), ap(n);
  double rr = static_cast<double>(n);
  const double stop = 1e-28 * rr;  // relative residual 1e-14
  for (std::size_t it = 0; it < 10 * n + 100 && rr > stop; ++it) {
    apply(p, ap);
    double pap = 0;
    for (std::size_t i = 0; i < n; ++i) pap += p[i] * ap[i];
    const double alpha = rr / pap;
    double rr_new = 0;
    for (std::size_t i = 0; i < n; ++i) {
      x[i] += alpha * p[i];
      r[i] -= alpha * ap[i];
      rr_new += r[i] * r[i];
    }
    const double beta = rr_new / rr;
    rr = rr_new;
    for (std::size_t i = 0; i < n; ++i) p[i] = r[i] + beta * p[i];
  }
  double sum = 0;
  for (double v : x) sum += v;
  return sum / static_cast<double>(n);
}

}  // namespace biota::models::flock
