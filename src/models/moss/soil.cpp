#include "models/moss/soil.hpp"

#include <algorithm>
#include <cmath>

namespace biota::models::moss {

const char* soil_type_name(SoilType t) {
  switch (t) {
    case SoilType::kHumus:
      return "humus";
    case SoilType::kSand:
      return "sand";
    case SoilType::kAsphalt:
      return "asphalt";
  }
  return "?";
}

SoilParams soil_params(SoilType t) {
  switch (t) {
    case SoilType::kHumus:
      return {2.16e2, 10.0, 0.490};
    case SoilType::kSand:
      return {8.32e5, 16.6, 0.392};
    case SoilType::kAsphalt:
      return {7.25e7, 19.4, 0.012};
  }
  return {};
}

double cloud_coefficient(double a) {
  return 0.826 * a * a * a - 1.234 * a * a + 1.135 * a + 0.298;
}

double atmospheric_radiation(double t, double c, const SoilConstants& k) {
  return k.sigma * t * t * t * t * (1.0 - 0.26 * c);
}

double heat_energy(double s, double l, const SoilConstants& k) {
  return (1.0 - k.albedo) * s + l;
}

double bulk_transfer(double m, double mmax, const SoilConstants& k) {
  if (mmax <= 0) return k.ch_min;
  return k.ch_min + (k.ch_max - k.ch_min) * std::clamp(m, 0.0, mmax) / mmax;
}

double saturation_vapour_pressure(double t) {
  return 6.1078 * std::pow(10.0, 7.5 * (t - 273.15) / (t - 35.85));
}

double saturation_specific_humidity(double t, double p) {
  const double e = saturation_vapour_pressure(t);
  return (0.622 * e / p) / (1.0 - 0.378 * e / p);
}

double dqsat_dt(double t, double p, DeltaForm form) {
  const double e = saturation_vapour_pressure(t);
  const double tail = 0.622 * p / ((p - 0.378 * e) * (p - 0.378 * e));
  if (form == DeltaForm::kPrinted)  // T in K where the formula wants °C, 6.1078 for e_SAT(T)
    return 6.1078 * (2500.0 - 2.4 * t) / (0.4615 * (273.15 + t) * (273.15 + t)) * tail;
  const double tc = t - 273.15;  // L_v = 2500 - 2.4 t J/g, R_v = 0.4615 J/(g K)
  return e * (2500.0 - 2.4 * tc) / (0.4615 * (273.15 + tc) * (273.15 + tc)) * tail;
}

double evaporation_ease(double theta, const SoilParams& s) {
  const double dry = s.theta_sat - std::clamp(theta, 0.0, s.theta_sat);
  return s.f1 * std::pow(dry, s.f2);
}

double evaporation_efficiency(double ch, double u, double f, const SoilConstants& k) {
  return 1.0 / (1.0 + ch * u * f / k.d_atm);
}

SoilDayState surface_balance(double insolation, double ch, double beta, const Weather& w,
                             const SoilConstants& k, DeltaForm form) {
  SoilDayState st;
  st.beta = beta;
  const double t = w.temperature;
  const double l = atmospheric_radiation(t, cloud_coefficient(w.sunshine_ratio), k);
  const double r = heat_energy(insolation, l, k);  // (3.4)
  const double qsat = saturation_specific_humidity(t, k.pressure);
  const double delta = dqsat_dt(t, k.pressure, form);
  const double sig_t4 = k.sigma * t * t * t * t;
  const double latent = k.iota * k.rho * beta * ch * w.wind;  // ιρβ C_H U
  st.delta_t = (r - sig_t4 - latent * qsat * (1.0 - w.humidity)) /
               (4.0 * k.sigma * t * t * t + k.cp_rho * ch * w.wind + latent * delta);  // (3.11)
  st.surface_temperature = t + st.delta_t;
  st.latent_flux = latent * (qsat * (1.0 - w.humidity) + delta * st.delta_t);  // (3.14)
  st.evaporation = st.latent_flux / k.iota;                                    // erratum 9

  double qsat_s = qsat + delta * st.delta_t;  // linearised q_SAT(T_s)
  if (!(qsat_s > 0)) {                        // erratum 6 guard
    qsat_s = saturation_specific_humidity(st.surface_temperature, k.pressure);
    st.humidity_guarded = true;
  }
  st.surface_humidity = beta + w.humidity * qsat * (1.0 - beta) / qsat_s;  // (3.16)
  return st;
}

SoilDayState soil_day(const SoilDayInput& in, const Weather& w, const SoilConstants& k,
                      DeltaForm form) {
  const SoilParams soil = soil_params(in.soil);
  const double h = std::clamp(in.depth_mm, 1.0, 1000.0);
  const double o_sat = h * soil.theta_sat;                                 // (3.7)
  const double wet = std::min(o_sat, std::max(0.0, in.bucket + in.rain));  // erratum 10
  const double theta = wet / h;                                            // (3.8)
  const double beta = evaporation_efficiency(in.ch, w.wind, evaporation_ease(theta, soil), k);
  SoilDayState st = surface_balance(in.insolation, in.ch, beta, w, k, form);
  st.theta = theta;
  st.bucket =
      std::min(o_sat, std::max(0.0, in.bucket + in.rain - 86400.0 * st.evaporation));  // (3.6)
  return st;
}

}  // namespace biota::models::moss
