#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <random>
#include <vector>

#include "core/quat.hpp"
#include "models/plants/seaweed_integrate.hpp"

using biota::core::Quat;
using biota::core::Real;
using biota::core::Vec3;
using namespace biota::models::plants;

// integrate_spheres runs 8-sphere vector lanes and a scalar tail; every sphere must get the bits
// of the symplectic Euler step written sphere by sphere with core::Quat::integrated, for spins
// below the series bound, above it (libm) and at rest.
TEST(SeaweedIntegrate, LanesGiveTheScalarStepsBits) {
  const std::size_t n = 8 * 5 + 3;
  const Real h = 1.0 / 1200, hm = h / 5e-4, hi = h / 5e-9;
  std::mt19937_64 gen(11);
  std::uniform_real_distribution<Real> u(-1, 1);
  std::vector<Real> col[19];
  for (auto& c : col) c.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 15; ++k) col[k][i] = u(gen);  // force, torque, v, omega, x
    for (int k = 3; k < 6; ++k) col[k][i] *= 1e-9;    // torques of nN m
    // Spins: most below the series bound (half-angle |w| h / 2 < 0.01), every 5th far above it
    // (libm), every 7th at rest.
    const Real spin = i % 5 == 0 ? 200.0 : (i % 7 == 0 ? 0.0 : 3.0);
    for (int k = 9; k < 12; ++k) col[k][i] *= spin;
    const Quat q = Quat::axis_angle(Vec3{u(gen), u(gen), 0.5}, u(gen) * 3).normalized();
    col[15][i] = q.w, col[16][i] = q.x, col[17][i] = q.y, col[18][i] = q.z;
  }
  for (std::size_t i = 0; i < n; i += 7) col[3][i] = col[4][i] = col[5][i] = 0;
  auto ref = col;  // the reference, stepped sphere by sphere
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 v =
        Vec3{ref[6][i], ref[7][i], ref[8][i]} + Vec3{ref[0][i], ref[1][i], ref[2][i]} * hm;
    const Vec3 w =
        Vec3{ref[9][i], ref[10][i], ref[11][i]} + Vec3{ref[3][i], ref[4][i], ref[5][i]} * hi;
    ref[6][i] = v.x, ref[7][i] = v.y, ref[8][i] = v.z;
    ref[9][i] = w.x, ref[10][i] = w.y, ref[11][i] = w.z;
    ref[12][i] = ref[12][i] + v.x * h, ref[13][i] = ref[13][i] + v.y * h;
    ref[14][i] = ref[14][i] + v.z * h;
    const Quat q = Quat{ref[15][i], ref[16][i], ref[17][i], ref[18][i]}.integrated(w, h);
    ref[15][i] = q.w, ref[16][i] = q.x, ref[17][i] = q.y, ref[18][i] = q.z;
  }
  const SphereColumns c{col[0].data(),  col[1].data(),  col[2].data(),  col[3].data(),
                        col[4].data(),  col[5].data(),  col[6].data(),  col[7].data(),
                        col[8].data(),  col[9].data(),  col[10].data(), col[11].data(),
                        col[12].data(), col[13].data(), col[14].data(), col[15].data(),
                        col[16].data(), col[17].data(), col[18].data()};
  integrate_spheres(c, n, h, hm, hi);
  for (int k = 6; k < 19; ++k)
    for (std::size_t i = 0; i < n; ++i)
      EXPECT_EQ(std::bit_cast<std::uint64_t>(col[k][i]), std::bit_cast<std::uint64_t>(ref[k][i]))
          << "column " << k << " sphere " << i;
}
