/// \file test_chaos_game.cpp
/// \brief Chaos game (eq. 6.1): attractor dimension, fern bounds, order and determinism.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "models/flock/box_counting.hpp"
#include "models/flock/chaos_game.hpp"

using biota::core::Vec3;
using biota::models::flock::box_counting_dimension;
using biota::models::flock::ChaosGame;

TEST(ChaosGame, SierpinskiGasketBoxDimension) {
  // 3^k boxes at level k; 2e6 points oversample the 3^9 = 19683 boxes of the finest level ~100×.
  const auto pts = ChaosGame::sierpinski_gasket().generate(2000000, 1);
  const auto bc = box_counting_dimension(pts, 2, 2, 9);
  std::printf("[ chaos ] gasket box dimension %.4f +- %.4f (log3/log2 = %.4f)\n", bc.dimension,
              bc.dimension_error, std::log(3.0) / std::log(2.0));
  EXPECT_NEAR(bc.dimension, std::log(3.0) / std::log(2.0), 0.03);
  for (const auto& p : pts) {  // inside the triangle (0,0), (1,0), (1/2,1)
    ASSERT_GE(p.y, -1e-12);
    ASSERT_LE(p.y, 2 * p.x + 1e-12);
    ASSERT_LE(p.y, 2 * (1 - p.x) + 1e-12);
    ASSERT_EQ(p.z, 0.0);
  }
}

TEST(ChaosGame, SierpinskiTetrahedronBoxDimension) {
  const auto pts = ChaosGame::sierpinski_tetrahedron().generate(2000000, 2);
  const auto bc = box_counting_dimension(pts, 3, 2, 8);
  std::printf("[ chaos ] tetrahedron box dimension %.4f +- %.4f (exact 2)\n", bc.dimension,
              bc.dimension_error);
  // The regular tetrahedron is not aligned with the dyadic boxes, so its faces cut boxes
  // unevenly; 0.05 covers that lattice effect at these levels.
  EXPECT_NEAR(bc.dimension, 2.0, 0.05);
}

TEST(ChaosGame, BarnsleyFernStaysInKnownBounds) {
  const auto pts = ChaosGame::barnsley_fern().generate(1000000, 3);
  double xmin = 1e9, xmax = -1e9, ymin = 1e9, ymax = -1e9;
  for (const auto& p : pts) {
    xmin = std::min(xmin, p.x), xmax = std::max(xmax, p.x);
    ymin = std::min(ymin, p.y), ymax = std::max(ymax, p.y);
  }
  std::printf("[ chaos ] fern x in [%.4f, %.4f], y in [%.4f, %.4f]\n", xmin, xmax, ymin, ymax);
  EXPECT_GE(xmin, -2.1820);
  EXPECT_LE(xmax, 2.6558);
  EXPECT_GE(ymin, 0.0);
  EXPECT_LE(ymax, 9.9983);
  // and it fills them: within 2% of each bound
  EXPECT_LT(xmin, -2.1820 + 0.1);
  EXPECT_GT(xmax, 2.6558 - 0.1);
  EXPECT_GT(ymax, 9.9983 - 0.2);
}

TEST(ChaosGame, GenerationOrderIsTheOrbitAndDeterministic) {
  const auto g = ChaosGame::barnsley_fern();
  const auto a = g.generate(10000, 7), b = g.generate(10000, 7), c = g.generate(10000, 8);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  EXPECT_NE(a, g.generate(10000, 7, 1));  // another stream id
  // Each point is the image of its predecessor under one of the maps (take-off order = orbit).
  for (std::size_t i = 1; i < a.size(); ++i) {
    bool found = false;
    for (const auto& m : g.maps()) {
      const Vec3 q = m.apply(a[i - 1]);
      // rounding may differ by FMA contraction between translation units
      found = found || biota::core::norm(q - a[i]) < 1e-12;
    }
    ASSERT_TRUE(found) << "point " << i;
  }
  // A prefix is stable: asking for fewer points gives the first ones.
  const auto short_run = g.generate(100, 7);
  EXPECT_TRUE(std::equal(short_run.begin(), short_run.end(), a.begin()));
}

TEST(ChaosGame, FlatMapsAndValidation) {
  // User-defined 2D maps equal the gasket preset; map frequencies follow the probabilities.
  const double flat[] = {0.5, 0, 0, 0.5, 0,    0,   0.5,   //
                         0.5, 0, 0, 0.5, 0.5,  0,   0.25,  //
                         0.5, 0, 0, 0.5, 0.25, 0.5, 0.25};
  const auto g = ChaosGame::from_flat(2, flat);
  EXPECT_EQ(g.maps().size(), 3u);
  EXPECT_EQ(g.maps()[2].t.x, 0.25);
  EXPECT_EQ(g.maps()[2].t.y, 0.5);
  EXPECT_EQ(g.start_point(), (Vec3{0, 0, 0}));
  const double flat3[] = {0.5, 0, 0, 0, 0.5, 0, 0, 0, 0.5, 1, 2, 3, 1.0};
  const auto g3 = ChaosGame::from_flat(3, flat3);
  const Vec3 fp = g3.start_point();  // fixed point of x/2 + T is 2T
  EXPECT_NEAR(fp.x, 2, 1e-12);
  EXPECT_NEAR(fp.y, 4, 1e-12);
  EXPECT_NEAR(fp.z, 6, 1e-12);
  // Map 0 has p = 1/2: the fraction of points in the lower-left half-size triangle (the image of
  // map 0) is 1/2; 5 standard errors of a binomial proportion from 1e5 draws is 0.008.
  const auto pts = g.generate(100000, 4);
  long lower_left = 0;
  for (const auto& p : pts) lower_left += (p.x < 0.5 && p.y < 0.5);
  EXPECT_NEAR(lower_left / 1e5, 0.5, 0.008);
  const double bad_len[] = {1, 2, 3};
  EXPECT_THROW(ChaosGame::from_flat(2, bad_len), std::invalid_argument);
  const double bad_p[] = {0.5, 0, 0, 0.5, 0, 0, 0.7};
  EXPECT_THROW(ChaosGame::from_flat(2, bad_p), std::invalid_argument);
}
