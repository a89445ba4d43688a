// Every layout / streaming variant of the layout experiment (tests/benchmarks/lbm_layout_bench.cpp)
// must reproduce the production sweep (variant (a)) bitwise on a small periodic box, so that none
// of them is fast because it is wrong. No timing here.
#include <gtest/gtest.h>

#include "../../benchmarks/lbm_layout_variants.hpp"
#include "solvers/lbm/lattice.hpp"

using namespace biota::bench::lbm_layout;
using biota::solvers::lbm::D3Q15;
using biota::solvers::lbm::D3Q19;

namespace {

constexpr int kN = 12;
constexpr int kSteps = 6;  // even, so the AA layout is natural at the end
constexpr double kTau = 0.6;

// Pull schemes store the post-collision state C(S(f)); push schemes (and AA after an even number
// of steps) store the pre-collision state S(C(f)). Starting the push scheme from S(f0) gives
// (S C)^N S f0 = S (C S)^N f0, i.e. the production state streamed once more: the comparison is
// then a pure index shift, with no arithmetic, so agreement must be bitwise.
template <class V, class L>
V evolve(int steps, bool pre_streamed) {
  V v(kN, kTau);
  init_state<L>(kN, [&](int q, int i, int j, int k, double x) {
    if (pre_streamed)
      v.set(q, wrap(i + L::c[q][0], kN), wrap(j + L::c[q][1], kN), wrap(k + L::c[q][2], kN), x);
    else
      v.set(q, i, j, k, x);
  });
  for (int s = 0; s < steps; ++s) v.step();
  return v;
}

template <class V, class L>
void expect_same_as_production(bool push) {
  const auto ref = evolve<SoaPull<L>, L>(kSteps, false);
  const auto var = evolve<V, L>(kSteps, push);
  const auto init = evolve<SoaPull<L>, L>(0, false);
  long differ = 0, moved = 0;
  for (int q = 0; q < L::Q; ++q)
    for (int k = 0; k < kN; ++k)
      for (int j = 0; j < kN; ++j)
        for (int i = 0; i < kN; ++i) {
          const double r = push ? ref.get(q, wrap(i - L::c[q][0], kN), wrap(j - L::c[q][1], kN),
                                          wrap(k - L::c[q][2], kN))
                                : ref.get(q, i, j, k);
          differ += r != var.get(q, i, j, k);
          moved += ref.get(q, i, j, k) != init.get(q, i, j, k);
        }
  EXPECT_EQ(differ, 0) << L::name << ": populations differing from the production sweep";
  EXPECT_GT(moved, L::Q * kN * kN * kN / 2) << "the flow must actually evolve";
}

template <class L>
class LayoutVariants : public ::testing::Test {};
using Lattices = ::testing::Types<D3Q15, D3Q19>;
TYPED_TEST_SUITE(LayoutVariants, Lattices);

TYPED_TEST(LayoutVariants, AosPullMatchesProduction) {
  expect_same_as_production<AosPull<TypeParam>, TypeParam>(false);
}
TYPED_TEST(LayoutVariants, SoaPushMatchesProduction) {
  expect_same_as_production<SoaPush<TypeParam>, TypeParam>(true);
}
TYPED_TEST(LayoutVariants, SoaAAMatchesProduction) {
  expect_same_as_production<SoaAA<TypeParam>, TypeParam>(true);
}
TYPED_TEST(LayoutVariants, SoaPullNtMatchesProduction) {
  expect_same_as_production<SoaPullNt<TypeParam>, TypeParam>(false);
}

// Mass is conserved by the periodic closure of every scheme (catches a lost ghost write).
TYPED_TEST(LayoutVariants, PeriodicClosureConservesMass) {
  using L = TypeParam;
  const auto v0 = evolve<SoaAA<L>, L>(0, false), v1 = evolve<SoaAA<L>, L>(kSteps, false);
  double m0 = 0, m1 = 0;
  for (int q = 0; q < L::Q; ++q)
    for (int k = 0; k < kN; ++k)
      for (int j = 0; j < kN; ++j)
        for (int i = 0; i < kN; ++i) {
          m0 += v0.get(q, i, j, k);
          m1 += v1.get(q, i, j, k);
        }
  EXPECT_NEAR(m1, m0, 1e-12 * m0);
}

}  // namespace
