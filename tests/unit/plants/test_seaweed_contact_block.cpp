#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <random>
#include <vector>

#include "models/plants/seaweed_contact_block.hpp"

using biota::core::Vec3;
using namespace biota::models::plants;

namespace {
bool same_bits(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

// The law as the seaweed model states it, scalar and with its early returns (the form the
// production code had before it was written branch-free for vector lanes): false when the pair
// does not touch, else the force and torque on the sphere of `side` (0: a, the lower id).
bool reference_contact(const SphereHot& a, const SphereHot& b, std::uint32_t side,
                       const ContactLaw& law, Vec3& f, Vec3& t) {
  const Vec3 d = a.x - b.x;
  const double ri = a.r, rj = b.r, d2 = biota::core::dot(d, d);
  if (d2 > (ri + rj) * (ri + rj) * (1 + 1e-9)) return false;
  const double dist = biota::core::norm(d);
  const double overlap = ri + rj - dist;
  if (overlap <= 0 || dist <= 0) return false;
  const Vec3 n = d / dist;
  const Vec3 vrel =
      (a.v + biota::core::cross(a.w, n * (-ri))) - (b.v + biota::core::cross(b.w, n * rj));
  const double vn = biota::core::dot(vrel, n);
  const double fn = std::max(0.0, law.k * overlap - law.c * vn);
  const Vec3 vt = vrel - n * vn;
  const double vtn = biota::core::norm(vt);
  Vec3 ft{};
  if (vtn > 0) ft = vt * (-std::min(law.mu_c * vtn, law.mu * fn) / vtn);
  const Vec3 F = n * fn + ft;
  f = side == 0 ? F : -F;
  t = side == 0 ? biota::core::cross(n * (-ri), ft) : biota::core::cross(n * rj, -ft);
  return true;
}
}  // namespace

// The vector block must give every pair the reference law's bits, on either sphere of the pair
// (the seaweed's results on 1, 2 and 3 ranks rest on this), and +0 where the pair does not touch.
TEST(SeaweedContactBlock, LanesGiveTheScalarLawsBitsOnBothSides) {
  const ContactLaw law{50, 0.01, 0.5, 0.01};
  std::mt19937_64 gen(7);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<SphereHot> hot(64);
  for (auto& h : hot) {
    // Centres within 2 cm of each other and radii of 5 mm: about half the pairs overlap.
    h.x = Vec3{u(gen), u(gen), u(gen)} * 0.01;
    h.v = Vec3{u(gen), u(gen), u(gen)} * 0.1;
    h.w = Vec3{u(gen), u(gen), u(gen)} * 3.0;
    h.r = 0.005 * (1 + 0.1 * u(gen));
  }
  hot[1].x = hot[0].x;  // coincident centres: the law's dist <= 0 case
  int touching = 0, apart = 0;
  for (std::uint32_t first = 0; first + kContactBlock <= hot.size(); first += 3) {
    std::uint32_t a[kContactBlock], b[kContactBlock];
    for (int l = 0; l < kContactBlock; ++l) a[l] = first, b[l] = (first + 1 + 7 * l) % 64;
    ContactBlockOut out;
    evaluate_contact_block(hot.data(), a, b, law, out);
    for (int l = 0; l < kContactBlock; ++l)
      for (int side = 0; side < 2; ++side) {
        Vec3 f, t;
        const bool touches = reference_contact(hot[a[l]], hot[b[l]], side, law, f, t);
        if (side == 0) touches ? ++touching : ++apart;
        // On a: (f, ta); on b: (-f, tb), as the seaweed adds them.
        const Vec3 fa{out.fx[l], out.fy[l], out.fz[l]};
        const Vec3 fb = side == 0 ? fa : Vec3{-fa.x, -fa.y, -fa.z};
        const Vec3 tb = side == 0 ? Vec3{out.tax[l], out.tay[l], out.taz[l]}
                                  : Vec3{out.tbx[l], out.tby[l], out.tbz[l]};
        for (int d = 0; d < 3; ++d) {
          if (touches) {
            EXPECT_TRUE(same_bits(fb[d], f[d])) << first << " " << l << " " << side;
            EXPECT_TRUE(same_bits(tb[d], t[d])) << first << " " << l << " " << side;
          } else {
            EXPECT_EQ(fb[d], 0.0);
            EXPECT_EQ(tb[d], 0.0);
          }
        }
      }
  }
  EXPECT_GT(touching, 20);
  EXPECT_GT(apart, 20);
}

// Head-on, no spin, no sliding: the normal spring-damper alone, F = (k overlap - c v_n) n.
TEST(SeaweedContactBlock, HeadOnPairIsTheNormalSpringDamper) {
  const ContactLaw law{50, 0.01, 0.5, 0.01};
  std::vector<SphereHot> hot(2);
  hot[0].x = {0, 0, 0}, hot[1].x = {0.009, 0, 0};
  hot[0].v = {0.2, 0, 0}, hot[1].v = {-0.1, 0, 0};
  hot[0].r = hot[1].r = 0.005;
  std::uint32_t a[kContactBlock], b[kContactBlock];
  for (int l = 0; l < kContactBlock; ++l) a[l] = 0, b[l] = 1;
  ContactBlockOut out;
  evaluate_contact_block(hot.data(), a, b, law, out);
  // n points from b to a (-x); the approach speed along n is v_n = (v_a - v_b) . n = -0.3 m/s.
  // The force on a is out.f, on b -out.f.
  const double expected = 50 * 0.001 - 0.01 * (-0.3);
  EXPECT_NEAR(out.fx[0], -expected, 1e-15);
  EXPECT_EQ(out.fy[0], 0.0);
  EXPECT_EQ(out.taz[0], 0.0);
  EXPECT_EQ(out.tbz[0], 0.0);
}
