// Soil model (3.2)-(3.16) against the digest's check values (spec moss.md section 3, "Check values
// derived from the paper's formulas") and the errata of section 5.
#include <gtest/gtest.h>

#include <cmath>

#include "models/moss/soil.hpp"

using namespace biota::models::moss;

namespace {
const SoilConstants k;
constexpr double kT15 = 288.15, kT20 = 293.15;

void expect_rel(double got, double want, double rel) {
  EXPECT_NEAR(got, want, std::abs(want) * rel) << "want " << want;
}
}  // namespace

TEST(MossSoil, CloudAndAtmosphericRadiation) {
  const double c = cloud_coefficient(6.0 / 8.0);
  expect_rel(c, 0.80359, 2e-5);
  expect_rel(k.sigma * std::pow(kT15, 4), 390.893, 2e-6);
  expect_rel(k.sigma * std::pow(kT20, 4), 418.738, 2e-6);
  expect_rel(atmospheric_radiation(kT15, c, k), 309.222, 2e-6);
  expect_rel(atmospheric_radiation(kT20, c, k), 331.249, 2e-6);
  EXPECT_DOUBLE_EQ(heat_energy(100.0, 300.0, k), 0.8 * 100.0 + 300.0);
}

TEST(MossSoil, SaturationHumidity) {
  expect_rel(saturation_vapour_pressure(kT15), 17.0523, 1e-5);
  expect_rel(saturation_vapour_pressure(kT20), 23.3809, 1e-5);
  expect_rel(saturation_specific_humidity(kT15, 1013), 0.010537, 5e-5);
  expect_rel(saturation_specific_humidity(kT20, 1013), 0.014483, 5e-5);
}

TEST(MossSoil, DeltaPrintedAndCorrected) {
  expect_rel(dqsat_dt(kT15, 1013, DeltaForm::kPrinted), 4.7245e-5, 1e-4);
  expect_rel(dqsat_dt(kT20, 1013, DeltaForm::kPrinted), 4.6326e-5, 1e-4);
  expect_rel(dqsat_dt(kT15, 1013, DeltaForm::kCorrected), 6.8193e-4, 1e-4);
  expect_rel(dqsat_dt(kT20, 1013, DeltaForm::kCorrected), 9.0328e-4, 1e-4);
  // Erratum 6: the corrected form is the derivative of (3.13) to 0.2 %.
  for (double t : {kT15, kT20}) {
    const double h = 1e-3;
    const double num =
        (saturation_specific_humidity(t + h, 1013) - saturation_specific_humidity(t - h, 1013)) /
        (2 * h);
    expect_rel(dqsat_dt(t, 1013, DeltaForm::kCorrected), num, 2e-3);
  }
  expect_rel(dqsat_dt(kT15, 1013, DeltaForm::kCorrected), 6.8273e-4, 2e-3);
}

TEST(MossSoil, SurfaceTemperatureCheckValues) {
  const Weather w;  // Table 4.3
  // Digest: beta = 1, C_H = 0.0015, corrected Delta.
  EXPECT_NEAR(surface_balance(0, 0.0015, 1, w, k, DeltaForm::kCorrected).delta_t, -13.15, 0.01);
  EXPECT_NEAR(surface_balance(50, 0.0015, 1, w, k, DeltaForm::kCorrected).delta_t, -6.91, 0.01);
  EXPECT_NEAR(surface_balance(200, 0.0015, 1, w, k, DeltaForm::kCorrected).delta_t, 11.82, 0.01);
}

TEST(MossSoil, EnergyBalanceCloses) {
  // (3.11) and (3.14) are the linearised balance R = sigma T^4 + 4 sigma T^3 dT + H + iota E.
  const Weather w;
  for (double s : {0.0, 30.0, 120.0})
    for (double beta : {1.0, 0.4}) {
      const auto st = surface_balance(s, 0.002, beta, w, k, DeltaForm::kCorrected);
      const double t = w.temperature;
      const double r = heat_energy(s, atmospheric_radiation(t, cloud_coefficient(0.75), k), k);
      const double h = k.cp_rho * 0.002 * w.wind * st.delta_t;
      const double out =
          k.sigma * std::pow(t, 4) + 4 * k.sigma * std::pow(t, 3) * st.delta_t + h + st.latent_flux;
      EXPECT_NEAR(out, r, 1e-9 * r);
    }
}

TEST(MossSoil, HumidityAboveOneOnShadedDrySoil) {
  // Erratum 6 consequence: with the corrected Delta, rh_s ~ 3.5 at S = 0 and beta = 0.5.
  const auto st = surface_balance(0, 0.0015, 0.5, Weather{}, k, DeltaForm::kCorrected);
  EXPECT_GT(st.surface_humidity, 3.0);
  EXPECT_LT(st.surface_humidity, 4.5);
  EXPECT_FALSE(st.humidity_guarded);
  // beta = 1 gives rh_s = 1 exactly.
  EXPECT_DOUBLE_EQ(
      surface_balance(80, 0.0015, 1, Weather{}, k, DeltaForm::kCorrected).surface_humidity, 1.0);
}

TEST(MossSoil, HumidityGuardWhenLinearisationFails) {
  // Cold night-like balance (tiny wind, cold sky) drives dT below -q_SAT/Delta: the exact
  // q_SAT(T_s) is used and rh_s stays finite and positive.
  Weather w;
  w.wind = 0.01;
  w.sunshine_ratio = 1.0;
  SoilConstants cold = k;
  cold.albedo = 1.0;
  const auto st = surface_balance(0, 0.0015, 0.05, w, cold, DeltaForm::kCorrected);
  const double qsat = saturation_specific_humidity(w.temperature, 1013);
  ASSERT_LT(qsat + dqsat_dt(w.temperature, 1013, DeltaForm::kCorrected) * st.delta_t, 0.0);
  EXPECT_TRUE(st.humidity_guarded);
  EXPECT_TRUE(std::isfinite(st.surface_humidity));
  EXPECT_GT(st.surface_humidity, 0.0);
}

TEST(MossSoil, BulkTransferAndEvaporationEfficiency) {
  EXPECT_DOUBLE_EQ(bulk_transfer(0, 10, k), 0.0015);
  EXPECT_DOUBLE_EQ(bulk_transfer(10, 10, k), 0.0030);
  EXPECT_DOUBLE_EQ(bulk_transfer(25, 10, k), 0.0030);  // m clamped to M (erratum 14)
  EXPECT_DOUBLE_EQ(bulk_transfer(5, 10, k), 0.00225);
  // Saturated soil: F = 0, beta = 1; dry humus: F1 theta_sat^F2.
  const auto humus = soil_params(SoilType::kHumus);
  EXPECT_DOUBLE_EQ(evaporation_ease(0.49, humus), 0.0);
  expect_rel(evaporation_ease(0.0, humus), 2.16e2 * std::pow(0.49, 10.0), 1e-14);
  EXPECT_DOUBLE_EQ(evaporation_efficiency(0.0015, 0.2, 0.0, k), 1.0);
  // Erratum 12: asphalt F < 1e-29 m at any water content, so beta = 1.
  EXPECT_LT(evaporation_ease(0.0, soil_params(SoilType::kAsphalt)), 1e-29);
}

TEST(MossSoil, BucketDayOrder) {
  // Erratum 10: theta from O_{i-1} + P_i capped at O_SAT, then O_i = clamp(O + P - 86400 E).
  SoilDayInput in;
  in.depth_mm = 100;
  in.soil = SoilType::kSand;
  in.bucket = 10;  // O_SAT = 39.2 mm
  in.rain = 5;
  in.insolation = 150;
  const auto st = soil_day(in, Weather{}, k, DeltaForm::kCorrected);
  EXPECT_DOUBLE_EQ(st.theta, 15.0 / 100.0);
  EXPECT_GT(st.evaporation, 0.0);
  EXPECT_NEAR(st.bucket, 15.0 - 86400 * st.evaporation, 1e-12);
  EXPECT_LT(86400 * st.evaporation, 5.0);  // daily evaporation of a few mm at most
  // Overflow runs off; depth clamps to [1, 1000] mm.
  in.bucket = 39.2;
  in.rain = 100;
  in.insolation = 0;
  auto wet = soil_day(in, Weather{}, k, DeltaForm::kCorrected);
  EXPECT_DOUBLE_EQ(wet.theta, 0.392);
  EXPECT_DOUBLE_EQ(wet.bucket, 39.2);
  in.depth_mm = 5000;
  in.bucket = 1e6;
  EXPECT_DOUBLE_EQ(soil_day(in, Weather{}, k, DeltaForm::kCorrected).bucket, 392.0);
  // A dry bucket never goes negative (erratum 9).
  in.depth_mm = 1;
  in.bucket = 0;
  in.rain = 0;
  in.insolation = 400;
  EXPECT_GE(soil_day(in, Weather{}, k, DeltaForm::kCorrected).bucket, 0.0);
}
