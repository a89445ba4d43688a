/// \file test_tree_stand.cpp
/// \brief A stand of trees in the wind's frame: the turtle frame (heading +y) turned into the
/// world (up +z), scaled to the site's height at the site's root; random sites at least
/// min_spacing apart, species in turn; the same stochastic species gives each tree id its own
/// shape; links of one tree that overlap at a fork are found as grown together.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "models/plants/branch_contacts.hpp"
#include "models/plants/tree_stand.hpp"

using namespace biota::models::plants;
using biota::core::Vec3;

namespace {
TreeSpecies paper_species(int derivations) {
  TreeSpecies sp;
  sp.lsystem = parse_lsystem("axiom: F\nangle: 20\nF -> F[+F]F[-F][F]\n", "paper_fig1");
  sp.derivations = derivations;
  return sp;
}
}  // namespace

TEST(TreeStand, WorldFrameScaleAndRoot) {
  // Fig. 1 after 2 derivations: 25 links, height 7 F steps, x in [-3 sin 20, 2 sin 20 + sin 40]
  // (docs/tree.md); scaled to 6.67 m at (8, 8, 0) in the world (z up) it stands in the x-z plane.
  const TreeSite site{0, 0, {8, 8, 0}, 6.67};
  NodeLinkParams p;
  const NodeLinkTree t = build_tree(paper_species(2), site, p, 1000000);
  ASSERT_EQ(t.size(), 26u);
  EXPECT_EQ(t.parents()[0], -1);
  EXPECT_EQ(t.positions()[0], (Vec3{8, 8, 0}));
  double zmax = 0, xmin = 1e9, xmax = -1e9;
  for (const Vec3& x : t.positions()) {
    EXPECT_EQ(x.y, 8.0);  // planar: turtle z = 0 -> world y = site y
    zmax = std::max(zmax, x.z);
    xmin = std::min(xmin, x.x), xmax = std::max(xmax, x.x);
  }
  const double s = 6.67 / 7, d = std::numbers::pi / 9;
  EXPECT_NEAR(zmax, 6.67, 1e-12);
  // The turtle's + turns towards -x (L = -x): the same x extents, since the map keeps x.
  EXPECT_NEAR(xmin, 8 - 3 * std::sin(d) * s, 1e-12);
  EXPECT_NEAR(xmax, 8 + (2 * std::sin(d) + std::sin(2 * d)) * s, 1e-12);
}

TEST(TreeStand, RandomSitesSpacingAndSpecies) {
  std::vector<TreeSpecies> sp(3, paper_species(1));
  sp[1].height = 5;
  sp[2].height = 4;
  const auto a = random_sites(42, 30, 0, 0, 30, 20, 0.5, 2.0, sp);
  const auto b = random_sites(42, 30, 0, 0, 30, 20, 0.5, 2.0, sp);
  ASSERT_EQ(a.size(), 30u);
  for (std::size_t t = 0; t < a.size(); ++t) {
    EXPECT_EQ(a[t].id, t);
    EXPECT_EQ(a[t].species, static_cast<int>(t % 3));
    EXPECT_EQ(a[t].height, sp[t % 3].height);
    EXPECT_EQ(a[t].base.z, 0.5);
    EXPECT_EQ(a[t].base, b[t].base);  // a function of (seed, tree) only
    EXPECT_TRUE(a[t].base.x >= 0 && a[t].base.x <= 30 && a[t].base.y >= 0 && a[t].base.y <= 20);
    for (std::size_t u = 0; u < t; ++u) EXPECT_GE(norm(a[t].base - a[u].base), 2.0);
  }
}

TEST(TreeStand, StochasticSpeciesDiffersByTreeId) {
  TreeSpecies sp;
  sp.lsystem = parse_lsystem("axiom: F\nangle: 25\nF -> (0.5) F[+F]F\nF -> (0.5) F[-F][&F]F\n",
                             "stochastic");
  sp.derivations = 4;
  NodeLinkParams p;
  const auto t0 = build_tree(sp, {0, 0, {1, 1, 0}, 5}, p, 1000000);
  const auto t0b = build_tree(sp, {0, 0, {1, 1, 0}, 5}, p, 1000000);
  const auto t1 = build_tree(sp, {1, 0, {1, 1, 0}, 5}, p, 1000000);
  EXPECT_EQ(t0.positions(), t0b.positions());
  EXPECT_NE(t0.positions(), t1.positions());
}

TEST(TreeStand, ForkLinksGrowTogether) {
  // A fork of two 0.25 m links at +-20 degrees on a trunk link, the right one with a vertical
  // child: the left link's end and the child's start are 2 x 0.25 sin 20 = 0.171 m apart. With
  // radii 0.1 (sum 0.2) they overlap at rest: grown together; with radii 0.05 (sum 0.1) not.
  // Links sharing a node are not listed (the joint), nor the trunk and the child (0.25 m apart).
  const double a = std::numbers::pi / 9, l = 0.25;
  const Vec3 p0{0, 0, 0}, p1{0, 0, l};
  const Vec3 left = p1 + Vec3{-l * std::sin(a), 0, l * std::cos(a)};
  const Vec3 right = p1 + Vec3{l * std::sin(a), 0, l * std::cos(a)};
  const Vec3 rc = right + Vec3{0, 0, l};
  auto caps = [&](double r) {
    return std::vector<Capsule>{{p0, p1, {}, {}, r, 0, 0, 1},
                                {p1, left, {}, {}, r, 0, 1, 2},
                                {p1, right, {}, {}, r, 0, 1, 3},
                                {right, rc, {}, {}, r, 0, 3, 4}};
  };
  const auto wide = overlapping_pairs(caps(0.1));
  ASSERT_EQ(wide.size(), 1u);
  EXPECT_EQ(wide[0], (std::pair<std::int64_t, std::int64_t>{2, 4}));
  EXPECT_TRUE(overlapping_pairs(caps(0.05)).empty());
}
