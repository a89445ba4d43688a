#include <gtest/gtest.h>

#include <cmath>

#include "solvers/lbm/collision.hpp"
#include "solvers/lbm/lattice.hpp"

using namespace biota::solvers::lbm;

template <class L>
class LatticeTest : public ::testing::Test {};
using Lattices = ::testing::Types<D3Q15, D3Q19>;
TYPED_TEST_SUITE(LatticeTest, Lattices);

TYPED_TEST(LatticeTest, IsotropyUpToSecondOrder) {
  using L = TypeParam;
  double w = 0, c1[3] = {0, 0, 0}, c2[3][3] = {};
  for (int i = 0; i < L::Q; ++i) {
    w += L::w[i];
    for (int a = 0; a < 3; ++a) {
      c1[a] += L::w[i] * L::c[i][a];
      for (int b = 0; b < 3; ++b) c2[a][b] += L::w[i] * L::c[i][a] * L::c[i][b];
    }
    // opposite is the negated velocity, and pairs are (odd, odd+1), which TRT relies on
    for (int a = 0; a < 3; ++a) EXPECT_EQ(L::c[L::opp[i]][a], -L::c[i][a]);
    if (i > 0) EXPECT_EQ(L::opp[i], i % 2 ? i + 1 : i - 1);
  }
  EXPECT_NEAR(w, 1.0, 1e-15);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(c1[a], 0.0, 1e-15);
    for (int b = 0; b < 3; ++b) EXPECT_NEAR(c2[a][b], a == b ? 1.0 / 3.0 : 0.0, 1e-15);
  }
}

TYPED_TEST(LatticeTest, EquilibriumHasTheRightMoments) {
  using L = TypeParam;
  const double rho = 1.07, u[3] = {0.03, -0.02, 0.05};
  double m = 0, j[3] = {0, 0, 0};
  for (int i = 0; i < L::Q; ++i) {
    const double f = equilibrium<L>(i, rho, u[0], u[1], u[2]);
    m += f;
    for (int a = 0; a < 3; ++a) j[a] += L::c[i][a] * f;
  }
  EXPECT_NEAR(m, rho, 1e-14);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(j[a], rho * u[a], 1e-14);
}

TYPED_TEST(LatticeTest, CollisionConservesMassAndAddsTheForce) {
  using L = TypeParam;
  for (bool trt : {false, true}) {
    double f[L::Q];
    for (int i = 0; i < L::Q; ++i) f[i] = L::w[i] * (1.0 + 0.01 * std::sin(1.0 + i));
    double m0 = 0, j0[3] = {0, 0, 0};
    for (int i = 0; i < L::Q; ++i) {
      m0 += f[i];
      for (int a = 0; a < 3; ++a) j0[a] += L::c[i][a] * f[i];
    }
    const double F[3] = {1e-4, -2e-4, 3e-5};
    double rho, ux, uy, uz;
    const Relaxation r = trt ? Relaxation::trt(0.7, 3.0 / 16.0) : Relaxation::bgk(0.7);
    if (trt)
      collide<L, true>(f, r, F[0], F[1], F[2], rho, ux, uy, uz);
    else
      collide<L, false>(f, r, F[0], F[1], F[2], rho, ux, uy, uz);
    double m1 = 0, j1[3] = {0, 0, 0};
    for (int i = 0; i < L::Q; ++i) {
      m1 += f[i];
      for (int a = 0; a < 3; ++a) j1[a] += L::c[i][a] * f[i];
    }
    EXPECT_NEAR(m1, m0, 1e-15);
    // Guo forcing: post-collision momentum = pre-collision momentum + F.
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(j1[a], j0[a] + F[a], 1e-15);
    EXPECT_NEAR(ux, (j0[0] + 0.5 * F[0]) / m0, 1e-15);
  }
}

TYPED_TEST(LatticeTest, TrtWithEqualRatesIsBgk) {
  using L = TypeParam;
  double a[L::Q], b[L::Q];
  for (int i = 0; i < L::Q; ++i) a[i] = b[i] = L::w[i] * (1.0 + 0.02 * std::cos(3.0 * i));
  const double tau = 0.8;
  Relaxation same{1.0 / tau, 1.0 / tau};
  double rho, ux, uy, uz;
  collide<L, false>(a, same, 1e-5, 0, 0, rho, ux, uy, uz);
  collide<L, true>(b, same, 1e-5, 0, 0, rho, ux, uy, uz);
  for (int i = 0; i < L::Q; ++i) EXPECT_NEAR(a[i], b[i], 1e-16);
}

TEST(Relaxation, MagicParameterDefinesOmegaMinus) {
  const auto r = Relaxation::trt(0.9, 3.0 / 16.0);
  EXPECT_NEAR((1.0 / r.omega_plus - 0.5) * (1.0 / r.omega_minus - 0.5), 3.0 / 16.0, 1e-15);
}
