#include <gtest/gtest.h>

#include <set>
#include <utility>
#include <vector>

#include "core/rng.hpp"
#include "particles/cell_list.hpp"

TEST(CellList, PairsEqualBruteForce) {
  const int n = 3000;
  std::vector<double> x(n), y(n), z(n);
  for (int i = 0; i < n; ++i) {
    biota::core::Rng r(1, i, 0, biota::core::RngPurpose::kTest);
    x[i] = r.uniform(0, 1);
    y[i] = r.uniform(-0.5, 0.2);
    z[i] = r.uniform(0, 3);
  }
  const double rc = 0.07;
  std::set<std::pair<std::size_t, std::size_t>> got, ref;
  biota::particles::CellList cl(x.data(), y.data(), z.data(), n, rc);
  cl.for_each_pair([&](std::size_t i, std::size_t j, double) {
    EXPECT_TRUE(got.insert({std::min(i, j), std::max(i, j)}).second) << "pair found twice";
  });
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      const double dx = x[i] - x[j], dy = y[i] - y[j], dz = z[i] - z[j];
      if (dx * dx + dy * dy + dz * dz < rc * rc) ref.insert({i, j});
    }
  EXPECT_EQ(got, ref);
  EXPECT_GT(ref.size(), 100u);
}
