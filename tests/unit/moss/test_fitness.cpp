// Fitness (3.17)-(3.20) and germination (3.24): the properties stated by the paper and the
// digest's check values (spec moss.md 2.7 and section 3).
#include <gtest/gtest.h>

#include <cmath>

#include "models/moss/fitness.hpp"

using namespace biota::models::moss;

TEST(MossFitness, HalfAtRangeEdges) {
  for (double n : {0.5, 1.0})
    for (auto [x0, x1] : {std::pair{274.15, 299.15}, std::pair{0.0, 60.0}}) {
      EXPECT_NEAR(factor_fitness(x0, x0, x1, n), 0.5, 1e-12);
      EXPECT_NEAR(factor_fitness(x1, x0, x1, n), 0.5, 1e-12);
    }
}

TEST(MossFitness, ToleranceRange) {
  // n = 1: g = s in [0, 1]; n = 0.5: g in [1/2 - 2^-1/2, 1/2 + 2^-1/2] (erratum 17, unclamped).
  EXPECT_DOUBLE_EQ(factor_fitness(1.0, 0.8, 1.2, 1.0), 1.0);
  EXPECT_NEAR(factor_fitness(1.0, 0.8, 1.2, 0.5), 0.5 + std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(factor_fitness(50.0, 0.8, 1.2, 0.5), 0.5 - std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(factor_fitness(50.0, 0.8, 1.2, 1.0), 0.0, 1e-12);
  const double x = 1.35;  // s = 0.3 about: g = s for n = 1
  EXPECT_DOUBLE_EQ(factor_fitness(x, 0.8, 1.2, 1.0), range_fit(x, 0.8, 1.2));
}

TEST(MossFitness, SpeciesAndGrowth) {
  const auto& sp = paper_species();
  ASSERT_EQ(sp.size(), 3u);
  EXPECT_DOUBLE_EQ(sp[1].s1, 40.0);
  EXPECT_DOUBLE_EQ(sp[2].tau_g, 0.075);
  // At the centre of every range G = (1/2 + 2^-n_rh) for n_T = n_S = 1.
  for (const auto& s : sp) {
    const double g = fitness(s, 0.5 * (s.t0 + s.t1), 0.5 * (s.rh0 + s.rh1), 0.5 * (s.s0 + s.s1));
    EXPECT_NEAR(g, 0.5 + std::pow(0.5, s.n_rh), 1e-12);
    EXPECT_NEAR(daily_growth(s, g), s.alpha_g * (g - s.tau_g), 1e-15);
  }
}

TEST(MossFitness, GerminationWindows) {
  const auto& sp = paper_species()[0];
  // Spores: half maximum at days 60 and 365, peak at 212.5; gemmae: peak at day 0.
  EXPECT_FALSE(germinates(sp, 1.0, 0.0, kSporeWindow));  // s(0) ~ 0.07 < 0.4
  EXPECT_TRUE(germinates(sp, 1.0, 212.5, kSporeWindow));
  EXPECT_TRUE(germinates(sp, 1.0, 0.0, kGemmaWindow));
  EXPECT_FALSE(germinates(sp, 1.0, 90.0, kGemmaWindow));  // s(90) ~ 0.21
  EXPECT_FALSE(germinates(sp, 0.39, 0.0, kGemmaWindow));  // G below tau_b = 0.4
}
