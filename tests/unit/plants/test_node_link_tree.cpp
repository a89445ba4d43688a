/// \file test_node_link_tree.cpp
/// \brief The node-link tree (tree paper section 3, eqs. 1-11): a single link oscillates at the
/// frequency its parameters predict; a tree with no wind and no gravity stays exactly at rest; a
/// horizontal link settles under gravity to the angle of the force balance; the paper's tree bends
/// more at 7 and 10 m/s than at 5 m/s after a gravity settling phase.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "models/plants/lsystem.hpp"
#include "models/plants/node_link_tree.hpp"

using namespace biota::models::plants;
using biota::core::Vec3;

namespace {

// Frequency (Hz) from the upward zero crossings of x(t) (linear interpolation), crossings a..b.
double crossing_frequency(NodeLinkTree& t, double dt, int steps, int a, int b) {
  std::vector<Vec3> wind(t.size());
  std::vector<double> times;
  double prev = t.positions()[1].x;
  for (int s = 1; s <= steps; ++s) {
    t.step(dt, wind);
    const double x = t.positions()[1].x;
    if (prev < 0 && x >= 0) times.push_back(dt * (s - 1 + prev / (prev - x)));
    prev = x;
  }
  EXPECT_GT(static_cast<int>(times.size()), b);
  return (b - a) / (times[b] - times[a]);
}

NodeLinkTree single_link(const NodeLinkParams& p) {
  NodeLinkTree t({{0, 0, 0}, {0, 1, 0}}, {-1, 0}, {0.03, 0.03}, p);
  t.positions()[1].x = 1e-4;  // the rest direction stays vertical
  return t;
}

NodeLinkTree paper_tree(const NodeLinkParams& p) {
  const auto ls = parse_lsystem("axiom: F\nderivations: 2\nangle: 20\nF -> F[+F]F[-F][F]\n", "p");
  const auto g = interpret(ls, derive(ls, {}));
  return NodeLinkTree(g, 6.67 / (g.hi.y - g.lo.y), {}, p);
}

}  // namespace

TEST(NodeLinkTree, SingleLinkFrequency) {
  // m x'' = -(pi r^2 K_r / l) x with m = pi r^2 l delta: omega = sqrt(K_r / delta) / l, so
  // f = sqrt(1e4 / 230) / (2 pi) = 1.0494 Hz for l = 1 m. The semi-implicit update (9)-(10) with
  // per-step damping c has z^2 - (1 + c - omega^2 dt^2) z + c = 0: cos(phi) = (1 + c -
  // omega^2 dt^2) / (2 sqrt c), f_d = phi / (2 pi dt).
  NodeLinkParams p;
  p.gravity = {};
  const double omega = std::sqrt(p.k_restore / p.density);
  auto discrete = [&](double c, double dt) {
    return std::acos((1 + c - omega * omega * dt * dt) / (2 * std::sqrt(c))) /
           (2 * std::numbers::pi * dt);
  };
  p.k_damp = 1;
  const double dt = 1e-3;
  auto t = single_link(p);
  const double f = crossing_frequency(t, dt, 10000, 1, 9);
  EXPECT_NEAR(f / discrete(1, dt), 1, 1e-4);
  EXPECT_NEAR(f / (omega / (2 * std::numbers::pi)), 1, 1e-4);  // omega dt = 0.0066
  // The paper's damping 0.83 per step at its calibration dt = 1/30 s: f_d = 1.007 Hz.
  p.k_damp = 0.83;
  auto d = single_link(p);
  const double fd = crossing_frequency(d, 1.0 / 30, 200, 0, 4);
  EXPECT_NEAR(fd / discrete(0.83, 1.0 / 30), 1, 1e-3);
  std::printf(
      "single link: f = %.5f Hz (undamped, dt 1e-3; predicted %.5f), damped %.5f Hz "
      "(predicted %.5f)\n",
      f, omega / (2 * std::numbers::pi), fd, discrete(0.83, 1.0 / 30));
}

TEST(NodeLinkTree, NoWindNoGravityStaysExactlyAtRest) {
  NodeLinkParams p;
  p.gravity = {};
  auto t = paper_tree(p);
  std::vector<Vec3> wind(t.size());
  for (int s = 0; s < 100; ++s) t.step(1.0 / 30, wind);
  for (std::size_t k = 0; k < t.size(); ++k) {
    EXPECT_EQ(t.positions()[k], t.initial_positions()[k]);
    EXPECT_EQ(t.velocities()[k], Vec3{});
  }
}

TEST(NodeLinkTree, GravityStaticEquilibrium) {
  // A horizontal link: tangential balance on the circle of radius l gives
  // tan(alpha) = m g / (k l) = l delta g / K_r = 230 * 9.8 / 1e4 = 0.2254 (sag 0.22 m for 1 m).
  NodeLinkParams p;
  NodeLinkTree t({{0, 0, 0}, {1, 0, 0}}, {-1, 0}, {0.03, 0.03}, p);
  std::vector<Vec3> wind(2);
  for (int s = 0; s < 900; ++s) t.step(1.0 / 30, wind);
  const Vec3 x = t.positions()[1];
  EXPECT_NEAR(-x.y / x.x, 230 * 9.8 / 1e4, 1e-9);
  EXPECT_NEAR(std::hypot(x.x, x.y), 1, 1e-14);
  EXPECT_LT(norm(t.velocities()[1]), 1e-9);
}

TEST(NodeLinkTree, TipDisplacementGrowsWithWindSpeed) {
  // With the paper's constants the Fig. 1 tree scaled to 6.67 m (links of 0.95 m) does not stand
  // under its own weight: the trunk carries the whole tree through the rigid links while (5)
  // restores each link with only pi r^2 K_r / l, so it buckles (the settling run below moves a
  // node by metres). The wind comparison therefore runs without gravity (docs/tree.md).
  NodeLinkParams p;
  const double dt = 1.0 / 30;
  auto fallen = paper_tree(p);
  std::vector<Vec3> calm(fallen.size());
  for (int s = 0; s < 600; ++s) fallen.step(dt, calm);
  std::printf(
      "paper Fig. 1 tree at 6.67 m under gravity alone, 20 s: max node displacement %.4g m\n",
      fallen.max_displacement());
  EXPECT_GT(fallen.max_displacement(), 1.0);
  p.gravity = {};
  double last = 0;
  for (double u : {5.0, 7.0, 10.0}) {
    auto t = paper_tree(p);
    std::vector<Vec3> wind(t.size(), Vec3{u, 0, 0});
    for (int s = 0; s < 90; ++s) t.step(dt, wind);  // 3 s of wind
    std::printf(
        "wind %.0f m/s, no gravity: max node displacement after 3 s %.4g m, max bending "
        "%.4g rad\n",
        u, t.max_displacement(), t.max_bending_angle());
    EXPECT_GT(t.max_displacement(), last);
    last = t.max_displacement();
  }
}
