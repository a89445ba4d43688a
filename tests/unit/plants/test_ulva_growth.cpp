#include <gtest/gtest.h>

#include <cmath>

#include "core/rng.hpp"
#include "models/plants/ulva_growth.hpp"

using namespace biota::models::plants;
using biota::core::Vec3;

namespace {
std::vector<Vec3> grid_seeds(int n, double spacing) {
  std::vector<Vec3> s;
  for (int i = 0; i < n; ++i) s.push_back({spacing * (i % 10), spacing * (i / 10), 0.0});
  return s;
}
}  // namespace

TEST(UlvaGrowth, CountsPerCycleMatchProbabilities) {
  // Without interference every trial is an independent Bernoulli(P_I) and every new bud draws
  // n ~ U{0,1,2} laterals; tolerances are 4 binomial (resp. sample-sum) standard deviations.
  GrowthParams gp;
  gp.interference = false;
  gp.cycles = 4;
  const int plants = 300;
  auto pop = grow_population(gp, grid_seeds(plants, 1.0));
  const double p = gp.p_grow;
  const double t0 = gp.initial_branches * plants;
  EXPECT_NEAR(pop.stats[0].tips_before, p * t0, 4 * std::sqrt(t0 * p * (1 - p)));
  for (const auto& st : pop.stats) {
    EXPECT_EQ(st.blocked, 0);
    EXPECT_EQ(st.successes, st.grown);
    const double n = st.trials;
    EXPECT_NEAR(st.grown, p * n, 4 * std::sqrt(n * p * (1 - p)));
    EXPECT_NEAR(st.laterals, 1.0 * st.grown, 4 * std::sqrt(st.grown * 2.0 / 3.0));
  }
  // Tips: those that rested plus (1 + laterals) per new bud.
  for (std::size_t c = 1; c < pop.stats.size(); ++c) {
    const auto& a = pop.stats[c - 1];
    EXPECT_EQ(pop.stats[c].tips_before, (a.trials - a.grown) + a.grown + a.laterals);
  }
}

TEST(UlvaGrowth, NoBudInsideAnotherBudsPersonalSpace) {
  GrowthParams gp;
  gp.cycles = 5;
  auto pop = grow_population(gp, grid_seeds(20, 0.08));  // crowded: many conflicts
  long long retries = 0, blocked = 0;
  for (const auto& st : pop.stats) retries += st.retries, blocked += st.blocked;
  EXPECT_GT(retries, 0);
  const auto& b = pop.buds;
  for (std::size_t i = 0; i < b.size(); ++i)
    for (std::size_t j = i + 1; j < b.size(); ++j)
      ASSERT_GE(biota::core::norm(b[i].pos - b[j].pos), gp.personal_radius)
          << "buds " << i << " and " << j;
  std::printf("buds %zu, retries %lld, blocked %lld\n", b.size(), retries, blocked);
}

TEST(UlvaGrowth, StemLengthsAndEnvironmentFactor) {
  GrowthParams gp;
  gp.env_centre = {0.5, 0.5, 0};
  gp.env_radius = 0.5;
  EXPECT_DOUBLE_EQ(environment_factor(gp, {0.5, 0.5, 0.3}), 1.0);
  EXPECT_DOUBLE_EQ(environment_factor(gp, {1.2, 0.5, 0.0}), 1.5);
  EXPECT_DOUBLE_EQ(environment_factor(gp, {0.5 + 0.25, 0.5, 0.0}), 1.25);
  // Far outside a tiny radius the ring number passes any int: still the outermost value (the
  // int cast alone gave a negative ring, so a factor below env_min).
  GrowthParams tiny = gp;
  tiny.env_radius = 1e-9;
  EXPECT_DOUBLE_EQ(environment_factor(tiny, {0.9, 0.5, 0.0}), 1.5);
  auto pop = grow_population(gp, grid_seeds(30, 0.2));
  for (const auto& bud : pop.buds) {
    if (bud.cycle == 0) continue;
    const auto& par = pop.buds[bud.parent];
    const double l = biota::core::norm(bud.pos - par.pos), e = environment_factor(gp, par.pos);
    EXPECT_GE(l, gp.length_min * e - 1e-12);
    EXPECT_LE(l, gp.length_max * e + 1e-12);
  }
}
