// Daily moss update (3.20)-(3.23) with errata 21-24: death rule, gemma trigger on the running
// maximum, spore trigger, and the gemma/spore direction distributions.
#include <gtest/gtest.h>

#include <cmath>

#include "models/moss/life_cycle.hpp"

using namespace biota::models::moss;
using biota::core::Rng;
using biota::core::RngPurpose;

TEST(MossLifeCycle, NewMossDiesOnFirstDecliningDay) {
  const auto& sp = paper_species()[0];  // tau_g 0.1, tau_d 0.1
  MossState st;
  const auto d = moss_day(sp, 0.05, false, st);  // D = 0.3 (0.05 - 0.1) < 0
  EXPECT_NEAR(d.growth, -0.015, 1e-15);
  EXPECT_TRUE(d.dies);
  MossState grown{1.0, 1.0, 10};
  EXPECT_FALSE(moss_day(sp, 0.05, false, grown).dies);  // declining but above tau_d
}

TEST(MossLifeCycle, GemmaeOnRunningMaximumOnly) {
  const auto& sp = paper_species()[0];
  MossState st{0.45, 0.45, 5};
  // G = 1: D = 0.27, crosses 0.5 -> one gemma.
  EXPECT_EQ(moss_day(sp, 1.0, false, st).gemmae, 1);
  EXPECT_NEAR(st.g_moss, 0.72, 1e-12);
  // Down and up again below the old maximum: no gemma (erratum 22).
  moss_day(sp, 0.0, false, st);                       // D = -0.03
  EXPECT_EQ(moss_day(sp, 0.2, false, st).gemmae, 0);  // D = +0.03, back to 0.72
  // A jump over two multiples gives two.
  MossState big{0.9, 0.9, 5};
  MossDay d;
  Species fast = sp;
  fast.alpha_g = 0.9;
  d = moss_day(fast, 1.3, false, big);  // D = 1.08 -> 1.98: crosses 1.0 and 1.5
  EXPECT_EQ(d.gemmae, 2);
}

TEST(MossLifeCycle, SporesNeedGrowthAboveTwoOnSporeDays) {
  const auto& sp = paper_species()[2];
  MossState st{2.1, 2.1, 50};
  EXPECT_FALSE(moss_day(sp, 0.5, false, st).spore);
  EXPECT_TRUE(moss_day(sp, 0.5, true, st).spore);
  EXPECT_FALSE(moss_day(sp, 0.0, true, st).spore);  // declining
  MossState small{1.5, 1.5, 50};
  EXPECT_FALSE(moss_day(sp, 0.5, true, small).spore);
}

TEST(MossLifeCycle, Directions) {
  const biota::core::Vec3 n{0, 0, 1};
  double mean_y = 0;
  int up = 0;
  const int k = 20000;
  for (int i = 0; i < k; ++i) {
    Rng rng(3, static_cast<std::uint64_t>(i), 0, RngPurpose::kTest);
    const auto g = gemma_direction(rng);
    EXPECT_NEAR(biota::core::norm(g), 1.0, 1e-12);
    mean_y += g.y / k;
    const auto s = spore_direction(n, rng);
    const double c = biota::core::dot(s, n);
    EXPECT_GT(std::abs(c), std::sqrt(0.5) - 1e-12);  // within 45° of +n or of -n
    up += c > 0;
  }
  EXPECT_NEAR(mean_y, 0.0, 4 * std::sqrt(1.0 / 3 / k));
  EXPECT_NEAR(up, k / 2, 4 * std::sqrt(k / 4.0));
}
