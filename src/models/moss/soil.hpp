#pragma once
/// \file soil.hpp
/// \brief Daily-mean soil surface state of the moss model (spec moss.md 2.6, eqs. 3.2 to 3.16):
/// heat energy, bulk transfer coefficient, bucket water content, evaporation efficiency, surface
/// temperature, latent heat flux and surface humidity, with the digest's errata fixed (section 5;
/// each fix is named where it is made, and listed in docs/moss.md).
///
/// Units as in the paper: temperatures in K, pressures and vapour pressures in hPa, radiation in
/// W/m², water in the bucket and soil depth in mm, wind in m/s. Pure functions, no state.
#include <string>

namespace biota::models::moss {

/// \brief Soil type of a surface point, from the terrain texture colour (spec 2.3).
enum class SoilType : int { kHumus = 0, kSand = 1, kAsphalt = 2 };
inline constexpr int kNumSoilTypes = 3;
const char* soil_type_name(SoilType t);

/// \brief Table 3.4. F1 in metres (erratum 7: F/D_ATM is a soil resistance in s/m).
struct SoilParams {
  double f1 = 0, f2 = 0, theta_sat = 0;
};
SoilParams soil_params(SoilType t);

/// \brief Tables 3.5 and 3.6 and the C_H bounds of 3.5.2. ι keeps the printed 2.543e6 J/kg
/// (erratum 8: probably a transposition of 2.453e6; kept for fidelity, selectable).
struct SoilConstants {
  double sigma = 5.67e-8;    ///< W m^-2 K^-4
  double pressure = 1013.0;  ///< hPa
  double albedo = 0.2;
  double d_atm = 2.54e-5;  ///< m^2/s (printed m^-2 s^-1, erratum 7)
  double iota = 2.543e6;   ///< J/kg
  double rho = 1.19;       ///< kg/m^3
  double cp_rho = 1.21e3;  ///< J K^-1 m^-3
  double ch_min = 0.0015;  ///< bare soil
  double ch_max = 0.0030;  ///< dense moss
};

/// \brief Which form of (3.15) is used (erratum 6).
enum class DeltaForm {
  kCorrected,  ///< e_SAT(T) and t = T - 273.15 °C: matches d q_SAT/dT of (3.13) to 0.1 %
  kPrinted,    ///< the paper's formula read literally with T in K (14-20 times too small)
};

/// \brief Daily weather (Table 4.3). Precipitation is handled per day by the caller.
struct Weather {
  double temperature = 288.15;   ///< T, K
  double humidity = 0.73;        ///< rh, 0..1
  double wind = 0.2;             ///< U, m/s
  double sunshine_ratio = 0.75;  ///< A = N / N0
};

/// (3.2) cloud-effect coefficient for atmospheric radiation, A = N/N0.
double cloud_coefficient(double sunshine_ratio);
/// (3.3) atmospheric (downward long-wave) radiation L = σ T⁴ (1 - 0.26 C), W/m².
double atmospheric_radiation(double temperature, double cloud, const SoilConstants& k);
/// (3.4) heat energy R = (1 - ref) S + L, W/m².
double heat_energy(double insolation, double atmospheric, const SoilConstants& k);
/// (3.5) C_H = C_Hmin + (C_Hmax - C_Hmin) m/M, m clamped to [0, M] (erratum 14); M = 0 gives
/// C_Hmin.
double bulk_transfer(double mosses_near, double mosses_max, const SoilConstants& k);
/// (3.12) Tetens saturation vapour pressure at T (K), hPa.
double saturation_vapour_pressure(double temperature);
/// (3.13) saturation specific humidity at T (K) and p (hPa), kg/kg.
double saturation_specific_humidity(double temperature, double pressure);
/// (3.15) Δ = d q_SAT / dT, 1/K, in the chosen form (erratum 6).
double dqsat_dt(double temperature, double pressure, DeltaForm form);
/// (3.9) F(θ) = F1 (θ_SAT - θ)^F2, m; θ is clamped to [0, θ_SAT] (erratum 9: O_i >= 0).
double evaporation_ease(double theta, const SoilParams& soil);
/// (3.10) β = (1 + C_H U F / D_ATM)^-1.
double evaporation_efficiency(double ch, double wind, double ease, const SoilConstants& k);

/// \brief Inputs of one soil point for one day.
struct SoilDayInput {
  double insolation = 0;  ///< S from the photon map, W/m²
  double ch = 0.0015;     ///< from (3.5)
  double bucket = 0;      ///< O_{i-1}, mm
  double rain = 0;        ///< P_i, mm
  double depth_mm = 1;    ///< h, mm (clamped to [1, 1000])
  SoilType soil = SoilType::kHumus;
};

/// \brief The day's soil state of one point.
struct SoilDayState {
  double theta = 0;                ///< (3.8) before evaporation (from O_{i-1} + P_i)
  double beta = 0;                 ///< (3.10)
  double delta_t = 0;              ///< (3.11) T_s - T, K
  double surface_temperature = 0;  ///< T_s, K
  double latent_flux = 0;          ///< (3.14) ιE, W/m²
  double evaporation = 0;          ///< E_i = ιE / ι, kg m^-2 s^-1 = mm/s (erratum 9)
  double surface_humidity = 0;     ///< (3.16) rh_s
  double bucket = 0;               ///< O_i, mm, after (3.6) and the run-off / dry clamps
  bool humidity_guarded = false;   ///< (3.16) used the exact q_SAT(T_s) (erratum 6 guard)
};

/// \brief (3.11), (3.14) and (3.16) for a given β: fills beta, delta_t, surface_temperature,
/// latent_flux, evaporation, surface_humidity and humidity_guarded of the result.
SoilDayState surface_balance(double insolation, double ch, double beta, const Weather& w,
                             const SoilConstants& k, DeltaForm form);

/// \brief One day of 3.5.1 to 3.5.4 in the order of 3.7, with the reading of erratum 10:
/// θ and β from O_{i-1} + P_i (capped at O_SAT), then T_s and ιE, then
/// O_i = min(O_SAT, max(0, O_{i-1} + P_i - 86400 E_i)).
///
/// (3.16) guard (erratum 6): when the linearised q_SAT(T_s) = q_SAT + Δ δT is not positive, the
/// exact q_SAT(T_s) of (3.13) is used instead. The result can
/// still exceed 1 where β < 1 on cold shaded soil; it is not clamped (spec 5.6, 5.19).
SoilDayState soil_day(const SoilDayInput& in, const Weather& w, const SoilConstants& k,
                      DeltaForm form);

}  // namespace biota::models::moss
