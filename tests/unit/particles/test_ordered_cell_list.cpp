// OrderedCellList: finds every pair within the cutoff (brute force), and visits neighbours in an
// order that depends only on positions and ids, not on the storage order.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <vector>

#include "core/rng.hpp"
#include "particles/ordered_cell_list.hpp"

using biota::core::GlobalId;
using biota::core::Rng;
using biota::core::RngPurpose;
using biota::particles::OrderedCellList;

TEST(OrderedCellList, MatchesBruteForceAndOrderIsStorageIndependent) {
  const std::size_t n = 500;
  const double rc = 0.7;
  std::vector<double> x(n), y(n), z(n);
  std::vector<GlobalId> id(n);
  for (std::size_t i = 0; i < n; ++i) {
    Rng r(1, i, 0, RngPurpose::kTest);
    x[i] = r.uniform(-2, 3), y[i] = r.uniform(0, 4), z[i] = r.uniform(1, 2.5);
    id[i] = 1000 + 7 * i;
  }
  auto visit = [&](const std::vector<std::size_t>& perm) {
    std::vector<double> px(n), py(n), pz(n);
    std::vector<GlobalId> pid(n);
    for (std::size_t k = 0; k < n; ++k)
      px[k] = x[perm[k]], py[k] = y[perm[k]], pz[k] = z[perm[k]], pid[k] = id[perm[k]];
    // Carried columns (three: the one-pass case; the slab test carries one): the id, -x and 2y
    // of each point, as reals.
    std::vector<double> cid(n), cnx(n), c2y(n);
    for (std::size_t k = 0; k < n; ++k)
      cid[k] = double(pid[k]), cnx[k] = -px[k], c2y[k] = 2 * py[k];
    const double* const carry[3] = {cid.data(), cnx.data(), c2y.data()};
    OrderedCellList cl;
    cl.build(px.data(), py.data(), pz.data(), pid.data(), n, {-10, -10, -10}, rc, 1, carry);
    // For each particle in original order: the sequence of neighbour ids.
    std::vector<std::vector<GlobalId>> seq(n);
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t i = perm[k];
      cl.for_each_near({px[k], py[k], pz[k]}, [&](std::size_t s) {
        EXPECT_EQ(cl.ids()[s], pid[cl.index(s)]);
        EXPECT_EQ(cl.carried(0)[s], double(cl.ids()[s]));
        EXPECT_EQ(cl.carried(1)[s], -cl.x()[s]);
        EXPECT_EQ(cl.carried(2)[s], 2 * cl.y()[s]);
        const double dx = cl.x()[s] - px[k], dy = cl.y()[s] - py[k], dz = cl.z()[s] - pz[k];
        if (cl.ids()[s] != pid[k] && dx * dx + dy * dy + dz * dz < rc * rc)
          seq[i].push_back(cl.ids()[s]);
      });
    }
    return seq;
  };
  std::vector<std::size_t> perm(n);
  std::iota(perm.begin(), perm.end(), 0);
  const auto a = visit(perm);
  std::reverse(perm.begin(), perm.end());
  std::rotate(perm.begin(), perm.begin() + 137, perm.end());
  const auto b = visit(perm);
  EXPECT_EQ(a, b);  // same order, not only the same set
  std::size_t pairs = 0;
  for (std::size_t i = 0; i < n; ++i) {
    std::vector<GlobalId> brute;
    for (std::size_t j = 0; j < n; ++j) {
      const double dx = x[j] - x[i], dy = y[j] - y[i], dz = z[j] - z[i];
      if (j != i && dx * dx + dy * dy + dz * dz < rc * rc) brute.push_back(id[j]);
    }
    auto got = a[i];
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, brute);
    pairs += brute.size();
  }
  EXPECT_GT(pairs, n);
}

TEST(OrderedCellList, RefusesNonFiniteAndFarStrayPoints) {
  const double nan = std::numeric_limits<double>::quiet_NaN(),
               inf = std::numeric_limits<double>::infinity();
  std::vector<double> x{0.1, 0.2, 0.3}, y{0.1, 0.2, 0.3}, z{0.1, 0.2, 0.3};
  const std::vector<GlobalId> id{1, 2, 3};
  OrderedCellList cl;
  for (double bad : {nan, inf, -inf}) {
    auto yb = y;
    yb[1] = bad;
    EXPECT_THROW(cl.build(x.data(), yb.data(), z.data(), id.data(), 3, {0, 0, 0}, 0.1),
                 std::runtime_error);
  }
  auto zb = z;
  zb[2] = 1e9;  // finite, but 1e10 bins away
  EXPECT_THROW(cl.build(x.data(), y.data(), zb.data(), id.data(), 3, {0, 0, 0}, 0.1),
               std::runtime_error);
  cl.build(x.data(), y.data(), z.data(), id.data(), 3, {0, 0, 0}, 0.1);  // usable again
  EXPECT_EQ(cl.size(), 3u);
  // Nine points: the range scan's four lanes (points 0-7) and its tail (point 8).
  std::vector<double> x9(9, 0.5), y9(9, 0.5), z9(9, 0.5);
  std::vector<GlobalId> id9(9);
  std::iota(id9.begin(), id9.end(), GlobalId{1});
  for (std::size_t at : {0u, 5u, 8u})
    for (double bad : {nan, inf, -inf}) {
      auto xb = x9;
      xb[at] = bad;
      EXPECT_THROW(cl.build(xb.data(), y9.data(), z9.data(), id9.data(), 9, {0, 0, 0}, 0.1),
                   std::runtime_error)
          << "point " << at;
    }
  x9[6] = 0.05, x9[8] = 0.95;  // the lowest in a lane, the highest in the tail: bins 0 .. 9
  cl.build(x9.data(), y9.data(), z9.data(), id9.data(), 9, {0, 0, 0}, 0.1);
  EXPECT_EQ(cl.bins_along(0), 10);
}

TEST(OrderedCellList, SlabsVisitEveryBinOnceInPlaneOrderWithinEachSlab) {
  const std::size_t n = 300;
  std::vector<double> x(n), y(n), z(n);
  std::vector<GlobalId> id(n);
  for (std::size_t i = 0; i < n; ++i) {
    Rng r(3, i, 0, RngPurpose::kTest);
    x[i] = r.uniform(0, 5), y[i] = r.uniform(0, 7), z[i] = r.uniform(0, 3);
    id[i] = i;
  }
  std::vector<double> zz(n);
  for (std::size_t i = 0; i < n; ++i) zz[i] = z[i] * z[i];
  const double* const carry[1] = {zz.data()};
  OrderedCellList cl;
  cl.build(x.data(), y.data(), z.data(), id.data(), n, {0, 0, 0}, 1.0, 1, carry);
  for (std::size_t k = 0; k < n; ++k) EXPECT_EQ(cl.carried(0)[k], zz[cl.index(k)]);
  const long long nbx = cl.bins_along(0), nby = cl.bins_along(1), nbz = cl.bins_along(2);
  ASSERT_EQ(static_cast<std::size_t>(nbx * nby * nbz), cl.bins());
  ASSERT_GE(nby, 6);
  for (long long rows : {0LL, 1LL, 2LL, 4LL, nby, nby + 5}) {
    std::vector<std::size_t> seen;
    cl.for_each_bin_in_slabs(rows, [&](std::size_t b) { seen.push_back(b); });
    ASSERT_EQ(seen.size(), cl.bins()) << rows << " rows per slab";
    std::vector<std::size_t> sorted = seen;
    std::sort(sorted.begin(), sorted.end());
    std::vector<std::size_t> all(cl.bins());
    std::iota(all.begin(), all.end(), 0);
    EXPECT_EQ(sorted, all) << rows << " rows per slab";
    // Slab by slab (rows of y), every z plane, x fastest.
    const long long r = std::max(rows, 1LL);
    std::size_t k = 0;
    for (long long y0 = 0; y0 < nby; y0 += r)
      for (long long bz = 0; bz < nbz; ++bz)
        for (long long by = y0; by < std::min(y0 + r, nby); ++by)
          for (long long bx = 0; bx < nbx; ++bx, ++k) {
            EXPECT_EQ(seen[k], static_cast<std::size_t>((bz * nby + by) * nbx + bx));
          }
    if (rows >= nby) {
      EXPECT_EQ(seen, all);  // one slab: the flat order
    }
  }
}

#include "particles/particle_set.hpp"

TEST(ParticleSet, ReorderOwnedPermutesEveryColumn) {
  biota::particles::ParticleLayout layout;
  const int a = layout.add_real("v", 3, true, true);
  const int u = layout.add_u64("tag", 1, true, false);
  biota::particles::ParticleSet s(layout);
  for (int i = 0; i < 5; ++i) {
    const std::size_t k = s.add_owned(100 + i, {double(i), 0, 0});
    s.set_vec3(a, k, {0, double(i), 0});
    s.u64(u)[k] = 7 * i;
  }
  s.reorder_owned({4, 2, 0, 1, 3});
  const int want[5] = {4, 2, 0, 1, 3};
  for (int m = 0; m < 5; ++m) {
    EXPECT_EQ(s.id(m), 100u + want[m]);
    EXPECT_EQ(s.pos(m).x, want[m]);
    EXPECT_EQ(s.vec3(a, m).y, want[m]);
    EXPECT_EQ(s.u64(u)[m], 7u * want[m]);
  }
  EXPECT_THROW(s.reorder_owned({0, 1}), std::invalid_argument);
}

TEST(ParticleSet, RemoveOwnedKeepsTheRestWholeInOrderOrNotAndDropsGhosts) {
  biota::particles::ParticleLayout layout;
  const int a = layout.add_real("v", 3, true, true);
  const int u = layout.add_u64("tag", 1, true, false);
  // Removal patterns: none, the first, the last, a run, scattered, all, the tail, alternate.
  const std::vector<std::vector<int>> patterns = {{},           {0},
                                                  {9},          {3, 4, 5},
                                                  {0, 2, 7, 8}, {0, 1, 2, 3, 4, 5, 6, 7, 8, 9},
                                                  {6, 7, 8, 9}, {1, 3, 5, 7, 9}};
  for (bool keep_order : {true, false})
    for (const auto& pat : patterns) {
      biota::particles::ParticleSet s(layout);
      for (int i = 0; i < 10; ++i) {
        const std::size_t k = s.add_owned(100 + i, {double(i), 0, 0});
        s.set_vec3(a, k, {0, double(i), 0});
        s.u64(u)[k] = 7 * i;
      }
      s.resize(10, 13);  // three ghosts, dropped by the removal
      std::vector<char> remove(10, 0);
      for (int i : pat) remove[i] = 1;
      s.remove_owned(remove, keep_order);
      std::vector<int> want;
      for (int i = 0; i < 10; ++i)
        if (!remove[i]) want.push_back(i);
      ASSERT_EQ(s.n_owned(), want.size());
      EXPECT_EQ(s.n_total(), want.size());
      // Each remaining particle whole (every column from the same original); in the original
      // order with keep_order, else the same set.
      std::vector<int> got;
      for (std::size_t m = 0; m < want.size(); ++m) {
        const int i = static_cast<int>(s.id(m)) - 100;
        got.push_back(i);
        EXPECT_EQ(s.pos(m).x, i);
        EXPECT_EQ(s.vec3(a, m).y, i);
        EXPECT_EQ(s.u64(u)[m], 7u * i);
      }
      if (!keep_order) std::sort(got.begin(), got.end());
      EXPECT_EQ(got, want) << (keep_order ? "in order" : "any order");
    }
}
