/// \file test_architecture.cpp
/// \brief The general stochastic architectural model (eq. 1-4 with P_C, P_A, P_I, P_B): the paper's
/// worked example with all probabilities 1 gives the deterministic counts (checked against a hand
/// derivation and the mean-field recursion); with probabilities < 1 the counts per cycle and type
/// over many independent plants match the expected counts within 4 standard errors (estimated from
/// the per-plant sample variance: each per-plant count is a sum of Bernoulli trials, the plants are
/// independent, so the total is approximately normal).
#include <gtest/gtest.h>

#include <cmath>

#include "models/plants/architecture.hpp"
#include "models/plants/ulva_growth.hpp"

using namespace biota::models::plants;

namespace {
GrowthParams general_params(const ArchitectureParams& a, int cycles) {
  GrowthParams gp;
  gp.general = true;
  gp.arch = a;
  gp.cycles = cycles;
  gp.initial_branches = 1;
  gp.interference = false;  // pure topology: counts must not depend on the geometry
  return gp;
}
}  // namespace

TEST(Architecture, KangExampleWithProbabilityOneIsDeterministic) {
  const auto a = ArchitectureParams::kang_example();
  const int cycles = 10;
  // Hand derivation (docs/seaweed.md): a PA1 apex grows 5 cycles (2 PA2 + 1 PA3 metamers, the
  // 2 PA2 metamers bear 1 PA3 lateral each), then becomes PA2 for 3 cycles (2 PA3 metamers),
  // then PA3 for 1 cycle (1 metamer) and stops; each PA3 lateral grows one PA3 metamer next cycle.
  const std::vector<std::vector<long long>> metamers = {{0, 2, 1}, {0, 2, 3}, {0, 2, 3}, {0, 2, 3},
                                                        {0, 2, 3}, {0, 0, 4}, {0, 0, 2}, {0, 0, 2},
                                                        {0, 0, 1}, {0, 0, 0}};
  const std::vector<std::vector<long long>> laterals = {{0, 0, 2}, {0, 0, 2}, {0, 0, 2}, {0, 0, 2},
                                                        {0, 0, 2}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0},
                                                        {0, 0, 0}, {0, 0, 0}};
  const auto pop = grow_population(general_params(a, cycles), {{0, 0, 0}});
  const auto ex = expected_counts(a, cycles);
  ASSERT_EQ(pop.stats.size(), static_cast<std::size_t>(cycles));
  for (int c = 0; c < cycles; ++c)
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(pop.stats[c].metamers_by_type[k], metamers[c][k]) << "cycle " << c + 1;
      EXPECT_EQ(pop.stats[c].laterals_by_type[k], laterals[c][k]) << "cycle " << c + 1;
      EXPECT_DOUBLE_EQ(ex[c].metamers[k], static_cast<double>(metamers[c][k]));
      EXPECT_DOUBLE_EQ(ex[c].laterals[k], static_cast<double>(laterals[c][k]));
    }
  long long total = 0;
  for (const auto& m : metamers)
    for (long long x : m) total += x;
  EXPECT_EQ(static_cast<long long>(pop.buds.size()), 1 + total);
}

TEST(Architecture, StochasticCountsMatchExpectations) {
  auto a = ArchitectureParams::kang_example();
  a.p_c = {0.95, 0.9, 0.85};
  a.p_a = {0.2, 0.1, 0.3};
  a.p_i = {0.9, 0.7, 0.8};
  a.p_b = {0.5, 0.6, 0.75};
  const int cycles = 9, plants = 3000;
  auto gp = general_params(a, cycles);
  gp.seed = 2024;
  std::vector<biota::core::Vec3> seeds(plants, {0.5, 0.5, 0.5});
  const auto pop = grow_population(gp, seeds);
  const auto ex = expected_counts(a, cycles);
  // Per-plant metamer counts by (cycle, type) from the buds.
  std::vector<double> per(static_cast<std::size_t>(plants) * cycles * 3, 0.0);
  for (const auto& b : pop.buds)
    if (b.cycle > 0)
      per[(static_cast<std::size_t>(b.plant) * cycles + b.cycle - 1) * 3 + b.type - 1] += 1;
  int checked = 0;
  double worst = 0;
  for (int c = 0; c < cycles; ++c)
    for (int k = 0; k < 3; ++k) {
      double sum = 0, sum2 = 0;
      for (int p = 0; p < plants; ++p) {
        const double x = per[(static_cast<std::size_t>(p) * cycles + c) * 3 + k];
        sum += x, sum2 += x * x;
      }
      EXPECT_EQ(static_cast<long long>(sum), pop.stats[c].metamers_by_type[k]);
      const double expected = plants * ex[c].metamers[k];
      const double var = sum2 / plants - (sum / plants) * (sum / plants);
      const double se = std::sqrt(plants * var) + 1e-12;
      if (expected == 0) {
        EXPECT_EQ(sum, 0.0) << "cycle " << c + 1 << " type " << k + 1;
        continue;
      }
      ++checked;
      worst = std::max(worst, std::abs(sum - expected) / se);
      EXPECT_NEAR(sum, expected, 4 * se) << "cycle " << c + 1 << " type " << k + 1;
    }
  // Cycle 1 growth units: exactly Binomial(plants, P_C (1 - P_A)) of type 1.
  const double q = a.p_c[0] * (1 - a.p_a[0]);
  EXPECT_NEAR(pop.stats[0].units_by_type[0], plants * q, 4 * std::sqrt(plants * q * (1 - q)));
  EXPECT_GE(checked, 15);
  std::printf("%d (cycle, type) metamer counts checked, worst |observed - expected| = %.2f SE\n",
              checked, worst);
}

TEST(Architecture, InvalidParametersAreRejected) {
  auto a = ArchitectureParams::kang_example();
  a.t_a = {2, 4, 0};
  EXPECT_THROW(a.validate(), std::invalid_argument);
  a = ArchitectureParams::kang_example();
  a.p_b = {1, 1.5, 1};
  EXPECT_THROW(a.validate(), std::invalid_argument);
  a = ArchitectureParams::kang_example();
  a.m_i.pop_back();
  EXPECT_THROW(a.validate(), std::invalid_argument);
}
