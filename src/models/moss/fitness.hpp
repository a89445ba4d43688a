#pragma once
/// \file fitness.hpp
/// \brief Environmental fitness and growth of a moss (spec moss.md 2.7, eqs. 3.17 to 3.21, 3.24)
/// and the three species of Table 4.2.
#include <array>
#include <string>

namespace biota::models::moss {

/// \brief Table 3.7 parameters of one species (values of Table 4.2).
struct Species {
  std::string name;
  double t0, t1, n_t;     ///< temperature range, K, and tolerance
  double rh0, rh1, n_rh;  ///< humidity range and tolerance
  double s0, s1, n_s;     ///< insolation range, W/m², and tolerance
  double alpha_g, tau_g;  ///< growth coefficient and threshold (3.20)
  double tau_b, tau_d;    ///< germination and death thresholds
};

/// \brief ギンゴケ (Bryum argenteum), ハイゴケ (Hypnum plumaeforme), スギゴケ (haircap), Table 4.2.
const std::array<Species, 3>& paper_species();

/// (3.18) Gaussian with full width at half maximum x1 - x0 (natural log, erratum 18).
double range_fit(double x, double x0, double x1);
/// (3.19) as printed: values in [1/2 - 2^-n, 1/2 + 2^-n]; below 0 and above 1 for n < 1
/// (erratum 17, not clamped).
double factor_fitness(double x, double x0, double x1, double n);
/// (3.17) G = g(T_s) g(rh_s) g(S).
double fitness(const Species& sp, double surface_temperature, double surface_humidity,
               double insolation);
/// (3.20) D = α_g (G - τ_g).
inline double daily_growth(const Species& sp, double g) {
  return sp.alpha_g * (g - sp.tau_g);
}

/// \brief Germination window of (3.24): L0, L1 in days.
struct GerminationWindow {
  double l0, l1;
};
inline constexpr GerminationWindow kSporeWindow{60.0, 365.0};
inline constexpr GerminationWindow kGemmaWindow{-60.0, 60.0};
/// (3.24) G g(L, L0, L1, 1) > τ_b.
bool germinates(const Species& sp, double g, double days_since_creation, GerminationWindow w);

}  // namespace biota::models::moss
