#include "models/moss/fitness.hpp"

#include <cmath>
#include <numbers>

namespace biota::models::moss {

const std::array<Species, 3>& paper_species() {
  static const std::array<Species, 3> s{{
      {"bryum", 274.15, 299.15, 1, 0.8, 1.2, 0.5, 0.0, 60.0, 1, 0.3, 0.1, 0.4, 0.1},
      {"hypnum", 276.15, 295.15, 1, 0.9, 1.1, 0.5, 0.0, 40.0, 1, 0.25, 0.1, 0.35, 0.15},
      {"polytrichum", 278.15, 297.15, 1, 0.85, 1.15, 1, 0.0, 50.0, 1, 0.3, 0.075, 0.37, 0.12},
  }};
  return s;
}

double range_fit(double x, double x0, double x1) {
  const double w = x1 - x0, c = 0.5 * (x1 + x0);
  return std::exp(-4.0 * std::numbers::ln2 / (w * w) * (x - c) * (x - c));
}

double factor_fitness(double x, double x0, double x1, double n) {
  const double s = range_fit(x, x0, x1);
  if (s > 0.5) return 0.5 + std::pow(s - 0.5, n);
  return 0.5 - std::pow(0.5 - s, n);
}

double fitness(const Species& sp, double ts, double rhs, double s) {
  return factor_fitness(ts, sp.t0, sp.t1, sp.n_t) * factor_fitness(rhs, sp.rh0, sp.rh1, sp.n_rh) *
         factor_fitness(s, sp.s0, sp.s1, sp.n_s);
}

bool germinates(const Species& sp, double g, double days, GerminationWindow w) {
  return g * factor_fitness(days, w.l0, w.l1, 1.0) > sp.tau_b;
}

}  // namespace biota::models::moss
