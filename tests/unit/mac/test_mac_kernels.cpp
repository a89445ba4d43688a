#include <gtest/gtest.h>

#include <cmath>

#include "core/error.hpp"
#include "solvers/mac/boundary.hpp"
#include "solvers/mac/kernels.hpp"

using namespace biota::solvers::mac;

TEST(MacKernels, Upwind2IsSecondOrder) {
  // d/dx sin(x) at x = 1 from both sides; the error must drop by 4 per halving of h.
  auto err = [](double h, double a) {
    auto f = [](double x) { return std::sin(x); };
    const double x = 1.0;
    const double d = upwind2(a, f(x - 2 * h), f(x - h), f(x), f(x + h), f(x + 2 * h)) / (2 * h);
    return std::fabs(d - a * std::cos(x));
  };
  for (double a : {1.0, -1.0}) {
    const double order = std::log2(err(0.02, a) / err(0.01, a));
    EXPECT_NEAR(order, 2.0, 0.05) << "a = " << a;
  }
}

TEST(MacKernels, LogProfile) {
  EXPECT_DOUBLE_EQ(log_profile(10, 5, 10, 0.03), 5);
  EXPECT_EQ(log_profile(0.01, 5, 10, 0.03), 0);
  EXPECT_LT(log_profile(2, 5, 10, 0.03), 5);
  EXPECT_GT(log_profile(20, 5, 10, 0.03), 5);
  // C = (0.41 / ln(z1/z0))^2
  EXPECT_NEAR(wall_drag_coefficient(0.1, 0.01), std::pow(0.41 / std::log(10.0), 2), 1e-15);
}

TEST(MacBoundary, ParseAndValidate) {
  EXPECT_EQ(parse_boundary_type("ground", "k"), BoundaryType::kGround);
  try {
    parse_boundary_type("slippy", "wind.boundary.x_lo");
    FAIL();
  } catch (const biota::core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("wind.boundary.x_lo"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("slippy"), std::string::npos);
  }
  Boundaries b;
  b[0][0].type = BoundaryType::kPeriodic;  // x_hi is still noslip
  EXPECT_THROW(validate(b, "wind.boundary."), biota::core::InputError);
  b[0][0].type = BoundaryType::kInflow;  // inflow without outflow
  EXPECT_THROW(validate(b, "wind.boundary."), biota::core::InputError);
  b[0][1].type = BoundaryType::kOutflow;
  EXPECT_NO_THROW(validate(b, "wind.boundary."));
}
