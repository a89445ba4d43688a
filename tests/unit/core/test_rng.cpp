#include <gtest/gtest.h>

#include <cmath>

#include "core/rng.hpp"

using biota::core::Rng;
using biota::core::RngPurpose;

TEST(Rng, SameKeyGivesSameStream) {
  Rng a(42, 7, 3, RngPurpose::kTest), b(42, 7, 3, RngPurpose::kTest);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(a.next_u64(), b.next_u64());
}

TEST(Rng, DifferentKeysGiveDifferentStreams) {
  Rng base(42, 7, 3, RngPurpose::kTest);
  Rng other_id(42, 8, 3, RngPurpose::kTest), other_step(42, 7, 4, RngPurpose::kTest),
      other_purpose(42, 7, 3, RngPurpose::kGrowth), other_seed(43, 7, 3, RngPurpose::kTest);
  const auto v = base.next_u64();
  EXPECT_NE(v, other_id.next_u64());
  EXPECT_NE(v, other_step.next_u64());
  EXPECT_NE(v, other_purpose.next_u64());
  EXPECT_NE(v, other_seed.next_u64());
}

TEST(Rng, UniformMomentsMatchTheory) {
  // Mean 1/2 and variance 1/12; tolerances are 5 standard errors of the estimators.
  const int n = 200000;
  double s = 0, s2 = 0;
  for (int id = 0; id < n; ++id) {
    Rng r(1, id, 0, RngPurpose::kTest);
    double u = r.uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    s += u;
    s2 += u * u;
  }
  const double mean = s / n, var = s2 / n - mean * mean;
  EXPECT_NEAR(mean, 0.5, 5 * std::sqrt(1.0 / 12 / n));
  EXPECT_NEAR(var, 1.0 / 12, 5 * std::sqrt(1.0 / 180 / n));
}

TEST(Rng, UniformIntCoversRangeEvenly) {
  Rng r(9, 0, 0, RngPurpose::kTest);
  int counts[3] = {0, 0, 0};
  const int n = 30000;
  for (int i = 0; i < n; ++i) {
    auto k = r.uniform_int(0, 2);
    ASSERT_GE(k, 0);
    ASSERT_LE(k, 2);
    ++counts[k];
  }
  for (int c : counts) EXPECT_NEAR(c, n / 3.0, 5 * std::sqrt(n * (1.0 / 3) * (2.0 / 3)));
}

TEST(Rng, NormalHasUnitVariance) {
  Rng r(5, 1, 2, RngPurpose::kTest);
  const int n = 100000;
  double s = 0, s2 = 0;
  for (int i = 0; i < n; ++i) {
    double x = r.normal();
    s += x;
    s2 += x * x;
  }
  EXPECT_NEAR(s / n, 0.0, 5 / std::sqrt(n));
  EXPECT_NEAR(s2 / n, 1.0, 5 * std::sqrt(2.0 / n));
}
