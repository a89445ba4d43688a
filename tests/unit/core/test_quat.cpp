#include <gtest/gtest.h>

#include <cmath>

#include "core/quat.hpp"

using biota::core::Quat;
using biota::core::Vec3;

// The exponential map in long double: the reference for both of integrated()'s branches.
static Quat exact_step(const Quat& q, const Vec3& w, double dt) {
  const long double wn =
      std::sqrt((long double)w.x * w.x + (long double)w.y * w.y + (long double)w.z * w.z);
  const long double h = 0.5L * wn * dt, s = std::sin(h) / wn;
  const Quat r{double(std::cos(h)), double(w.x * s), double(w.y * s), double(w.z * s)};
  return (r * q).normalized();
}

TEST(Quat, IntegratedMatchesTheExponentialMapToRoundOff) {
  const Quat q0 = Quat{0.9, 0.1, -0.3, 0.2}.normalized();
  // Half-angles from 1e-9 to 0.5 rad: the series branch (below 0.01) and libm's.
  for (double angle = 2e-9; angle < 1.0; angle *= 1.7) {
    const Vec3 axis{0.48, -0.6, 0.64};  // unit
    const double dt = 1e-3, wn = angle / dt;
    const Vec3 w{axis.x * wn, axis.y * wn, axis.z * wn};
    const Quat a = q0.integrated(w, dt), b = exact_step(q0, w, dt);
    EXPECT_NEAR(a.w, b.w, 4e-16) << angle;
    EXPECT_NEAR(a.x, b.x, 4e-16) << angle;
    EXPECT_NEAR(a.y, b.y, 4e-16) << angle;
    EXPECT_NEAR(a.z, b.z, 4e-16) << angle;
  }
}

TEST(Quat, IntegratedQuarterTurnAndRest) {
  const Quat q = Quat{}.integrated({0, 0, std::acos(-1.0)}, 0.5);  // 90 degrees about z
  EXPECT_NEAR(q.w, std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(q.z, std::sqrt(0.5), 1e-15);
  const Quat p{0.6, 0.8, 0, 0};
  const Quat r = p.integrated({0, 0, 0}, 1e-3);  // no rotation: unchanged, bit for bit
  EXPECT_EQ(r.w, p.w);
  EXPECT_EQ(r.x, p.x);
}
