#include <gtest/gtest.h>

#include <set>
#include <tuple>
#include <utility>
#include <vector>

#include "core/rng.hpp"
#include "particles/cell_list.hpp"

namespace {

struct Points {
  std::vector<double> x, y, z;
};

Points random_points(int n, double lx, double ly, double lz, std::uint64_t seed) {
  Points p;
  for (int i = 0; i < n; ++i) {
    biota::core::Rng r(seed, i, 0, biota::core::RngPurpose::kTest);
    p.x.push_back(r.uniform(0, lx));
    p.y.push_back(r.uniform(-0.5, -0.5 + ly));
    p.z.push_back(r.uniform(0, lz));
  }
  return p;
}

// Every pair closer than rc exactly once, with r2 = ((xi - xj)^2 + (yi - yj)^2) + (zi - zj)^2
// bit for bit (the seaweed lists and their contact filter rely on that expression).
void expect_brute_force_pairs(const Points& p, double rc) {
  const std::size_t n = p.x.size();
  std::set<std::pair<std::size_t, std::size_t>> got, ref;
  biota::particles::CellList cl(p.x.data(), p.y.data(), p.z.data(), n, rc);
  cl.for_each_pair([&](std::size_t i, std::size_t j, double r2) {
    ASSERT_NE(i, j);
    EXPECT_TRUE(got.insert({std::min(i, j), std::max(i, j)}).second) << "pair found twice";
    const double dx = p.x[i] - p.x[j], dy = p.y[i] - p.y[j], dz = p.z[i] - p.z[j];
    EXPECT_EQ(r2, dx * dx + dy * dy + dz * dz);
  });
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      const double dx = p.x[i] - p.x[j], dy = p.y[i] - p.y[j], dz = p.z[i] - p.z[j];
      if (dx * dx + dy * dy + dz * dz < rc * rc) ref.insert({i, j});
    }
  EXPECT_EQ(got, ref);
}

}  // namespace

TEST(CellList, PairsEqualBruteForce) {
  const Points p = random_points(3000, 1, 0.7, 3, 1);
  expect_brute_force_pairs(p, 0.07);
  // Dense enough that bins hold tens of points (runs longer than a vector).
  const Points dense = random_points(4000, 0.3, 0.3, 0.3, 2);
  expect_brute_force_pairs(dense, 0.05);
}

TEST(CellList, PairsEqualBruteForceInFlatAndTinySets) {
  expect_brute_force_pairs(random_points(2000, 2, 1, 0, 3), 0.08);     // one bin in z
  expect_brute_force_pairs(random_points(1500, 5, 0, 0, 4), 0.02);     // one row of bins
  expect_brute_force_pairs(random_points(5, 0.01, 0.01, 0.01, 5), 1);  // one bin, a tail only
  expect_brute_force_pairs(random_points(1, 1, 1, 1, 6), 0.5);
  expect_brute_force_pairs(Points{}, 0.5);
}

TEST(CellList, PairCountOfAKnownLattice) {
  // A 10 x 10 x 10 unit lattice with rc = 1.5: each interior pair at distance 1 or sqrt 2 (face
  // and edge neighbours), none at sqrt 3 = 1.73. Face pairs 3 * 9 * 100, edge pairs 6 * 9 * 9 *
  // 10.
  Points p;
  for (int k = 0; k < 10; ++k)
    for (int j = 0; j < 10; ++j)
      for (int i = 0; i < 10; ++i) p.x.push_back(i), p.y.push_back(j), p.z.push_back(k);
  long long count = 0;
  biota::particles::CellList cl(p.x.data(), p.y.data(), p.z.data(), p.x.size(), 1.5);
  cl.for_each_pair([&](std::size_t, std::size_t, double) { ++count; });
  EXPECT_EQ(count, 3 * 9 * 100 + 6 * 9 * 9 * 10);
}
