/// \file test_branch_contacts.cpp
/// \brief Branch collisions (capsules, penalty + friction): closest points of segments, the
/// penalty force of a known overlap, action = reaction (forces sum to zero), links sharing a node
/// ignored, and two trees pushed together by the wind: without contacts the pushed tree's tip
/// passes through the other tree; with them it stops at contact and pushes the other tree away.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "models/plants/branch_contacts.hpp"
#include "models/plants/node_link_tree.hpp"

using namespace biota::models::plants;
using biota::core::Vec3;

TEST(BranchContacts, ClosestPoints) {
  double s, t;
  // Crossing at right angles, 0.1 apart: closest points at the middles.
  closest_points({-1, 0, 0}, {1, 0, 0}, {0, -1, 0.1}, {0, 1, 0.1}, s, t);
  EXPECT_DOUBLE_EQ(s, 0.5);
  EXPECT_DOUBLE_EQ(t, 0.5);
  // Parallel side by side, q shifted up by half: the middle of the overlap [0.5, 1] of p.
  closest_points({0, 0, 0}, {0, 0, 1}, {0.1, 0, 0.5}, {0.1, 0, 1.5}, s, t);
  EXPECT_DOUBLE_EQ(s, 0.75);
  EXPECT_DOUBLE_EQ(t, 0.25);
  // An end against a segment's interior.
  closest_points({0, 0, 0}, {0, 0, 1}, {0.3, 0, 2}, {-0.3, 0, 2}, s, t);
  EXPECT_DOUBLE_EQ(s, 1.0);
  EXPECT_DOUBLE_EQ(t, 0.5);
}

TEST(BranchContacts, PenaltyFrictionAndActionReaction) {
  ContactParams p;
  p.stiffness = 1000;
  p.friction = 0.5;
  p.viscous = 10;
  // Two crossing capsules of radius 0.05 whose axes are 0.08 apart: overlap 0.02, F_n = 20 N.
  // Capsule 1 slides along +y at 0.1 m/s: viscous 1 N < mu F_n = 10 N, so friction 1 N along -y.
  std::vector<Capsule> c(2);
  c[0] = {{-1, 0, 0}, {1, 0, 0}, {}, {}, 0.05, 0, 0, 1};
  c[1] = {{0, -1, 0.08}, {0, 1, 0.08}, {0, 0.1, 0}, {0, 0.1, 0}, 0.05, 1, 0, 1};
  std::vector<Vec3> fa, fb;
  EXPECT_EQ(capsule_forces(c, {0, 1}, p, fa, fb), 2);
  const Vec3 f0 = fa[0] + fb[0], f1 = fa[1] + fb[1];
  EXPECT_NEAR(f1.z, 20, 1e-9);
  EXPECT_NEAR(f1.y, -1, 1e-12);
  EXPECT_NEAR(f0.z, -20, 1e-9);
  EXPECT_NEAR(f0.y, 1, 1e-12);
  EXPECT_NEAR(norm(f0 + f1), 0, 1e-12);
  EXPECT_NEAR(fa[1].z, 10, 1e-9);  // contact at the middle: half to each node
  // Fast sliding: Coulomb limit mu F_n = 10 N.
  c[1].va = c[1].vb = {0, 5, 0};
  capsule_forces(c, {0, 1}, p, fa, fb);
  EXPECT_NEAR((fa[1] + fb[1]).y, -10, 1e-9);
  // Links of one tree sharing a node (the joint) never touch; other links of the tree do.
  c[1].tree = 0;
  c[1].node_a = 1, c[1].node_b = 2;
  EXPECT_EQ(capsule_forces(c, {0, 1}, p, fa, fb), 0);
  c[1].node_a = 3, c[1].node_b = 4;
  EXPECT_EQ(capsule_forces(c, {0, 1}, p, fa, fb), 2);
}

namespace {

// Tip x of two single-link trees (1 m, r 0.05 m, K_r = 100 so that the wind bends them by
// decimetres) 0.2 m apart along x; the wind (20 m/s along +x) blows on tree A only.
struct PairResult {
  double tip_a, tip_b, min_axis_distance;
};
PairResult push_pair(bool contacts) {
  NodeLinkParams p;
  p.gravity = {};
  p.k_restore = 100;
  NodeLinkTree a({{0, 0, 0}, {0, 0, 1}}, {-1, 0}, {0.05, 0.05}, p);
  NodeLinkTree b({{0.2, 0, 0}, {0.2, 0, 1}}, {-1, 0}, {0.05, 0.05}, p);
  ContactParams cp;
  const std::vector<Vec3> wind_a{{}, {20, 0, 0}}, calm(2);
  const double dt = 1.0 / 300;
  double dmin = 1e300;
  for (int s = 0; s < 20 * 300; ++s) {  // 20 s: the links swing at 0.1 Hz
    std::vector<Vec3> ea(2), eb(2);
    if (contacts) {
      std::vector<Capsule> c(2);
      c[0] = {a.positions()[0], a.positions()[1], {}, a.velocities()[1], 0.05, 0, 0, 1};
      c[1] = {b.positions()[0], b.positions()[1], {}, b.velocities()[1], 0.05, 1, 0, 1};
      std::vector<Vec3> fa, fb;
      capsule_forces(c, {0, 1}, cp, fa, fb);
      ea[1] = fb[0];  // node 0 is the fixed root
      eb[1] = fb[1];
    }
    a.step(dt, wind_a, nullptr, &ea);
    b.step(dt, calm, nullptr, &eb);
    double s0, t0;
    closest_points(a.positions()[0], a.positions()[1], b.positions()[0], b.positions()[1], s0, t0);
    const Vec3 pa = a.positions()[0] + s0 * (a.positions()[1] - a.positions()[0]);
    const Vec3 pb = b.positions()[0] + t0 * (b.positions()[1] - b.positions()[0]);
    dmin = std::min(dmin, norm(pa - pb));
  }
  return {a.positions()[1].x, b.positions()[1].x, dmin};
}

}  // namespace

TEST(BranchContacts, TwoTreesPushedTogether) {
  // Free deflection of A: F_w / k = K_w U 2 pi r l / (pi r^2 K_r / l) = 0.08 * 20 * 2 / (0.05 *
  // 100) = 0.64 m for small angles (the rigid link leans less), far past B at 0.2 m.
  const PairResult free = push_pair(false), hit = push_pair(true);
  std::printf("without contacts: tip A %.4f m, tip B %.4f m, closest axes %.4f m\n", free.tip_a,
              free.tip_b, free.min_axis_distance);
  std::printf("with contacts:    tip A %.4f m, tip B %.4f m, closest axes %.4f m\n", hit.tip_a,
              hit.tip_b, hit.min_axis_distance);
  EXPECT_GT(free.tip_a, 0.4);               // A passes through B
  EXPECT_EQ(free.tip_b, 0.2);               // B in calm air stays put exactly
  EXPECT_LT(free.min_axis_distance, 1e-3);  // the axes cross
  // With contacts A stops at B and both lean. Linear springs: k x_A + k x_B = F_w = k x_free
  // with x_A - x_B = 0.2 - 0.1 (touching), so B is pushed by (x_free - 0.1) / 2; the rigid
  // links at ~25 degrees are not linear springs, hence 15 %.
  const double expected = 0.5 * (free.tip_a - 0.1);
  EXPECT_NEAR(hit.tip_b - 0.2, expected, 0.15 * expected);
  EXPECT_LT(hit.tip_a, hit.tip_b);               // A stays on its side
  EXPECT_GT(hit.min_axis_distance, 0.1 - 0.03);  // overlap at most F / k_c = 3 cm
}
