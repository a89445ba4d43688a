// The production AA sweep (aa_stream_collide, whose whole vectors run on explicit registers,
// aa_simd.hpp) must give exactly the bits of `collide` applied cell by cell, for every template
// case it has: both lattices, BGK and TRT, no force / a uniform force / a force field with force
// spans, solids, the macroscopic outputs, both kinds of step. Rows of 13 cells, so every row has
// whole vectors and a scalar tail, and force spans that start and end inside a vector.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <vector>

#include "solvers/lbm/aa_sweep.hpp"
#include "solvers/lbm/lattice.hpp"

using namespace biota;
using namespace biota::solvers::lbm;

namespace {

constexpr int kNx = 13, kNy = 4, kNz = 3;

/// Deterministic values in [0, 1) (no RNG state shared between cases).
double hashed(std::uint64_t i) {
  i = (i ^ (i >> 31)) * 0x7fb5d329728ea185ULL;
  i = (i ^ (i >> 27)) * 0x81dadef4bc2dd44dULL;
  return double(i >> 11) * 0x1.0p-53;
}

template <class L, bool kTrt, ForceMode kForce, bool kMacro, bool kSolids, bool kFromPost>
void expect_bits_of_collide() {
  constexpr int Q = L::Q;
  grid::Field<double> f({kNx, kNy, kNz}, Q, 1), force({kNx, kNy, kNz}, 3, 1);
  grid::Field<double> rho({kNx, kNy, kNz}, 1, 1), u({kNx, kNy, kNz}, 3, 1);
  for (std::size_t i = 0; i < f.plane_size() * Q; ++i) f.data()[i] = 0.05 * (1.0 + 0.2 * hashed(i));
  for (std::size_t i = 0; i < rho.plane_size(); ++i) rho.data()[i] = -1.0 - hashed(i + 7);
  for (std::size_t i = 0; i < u.plane_size() * 3; ++i) u.data()[i] = -2.0 - hashed(i + 11);
  // A force in the cells [lo, hi) of each row (+0 elsewhere, as the spans promise), a -0 in one.
  std::vector<int> lo(kNy * kNz), hi(kNy * kNz);
  for (int k = 0; k < kNz; ++k)
    for (int j = 0; j < kNy; ++j) {
      const int r = j + kNy * k;
      lo[r] = (3 * r) % 7, hi[r] = kNx - (r % 4);
      for (int i = lo[r]; i < hi[r]; ++i)
        for (int c = 0; c < 3; ++c)
          force(i, j, k, c) = 1e-4 * (hashed(1000 * r + 10 * i + c) - 0.5);
    }
  force(5, 1, 1, 2) = -0.0;
  std::vector<std::uint8_t> solid(f.plane_size() + 8, 0);
  for (int k = 0; k < kNz; ++k)
    for (int j = 0; j < kNy; ++j)
      for (int i = 0; i < kNx; ++i) solid[f.index(i, j, k)] = hashed(97 * f.index(i, j, k)) < 0.2;
  const Relaxation relax = kTrt ? Relaxation::trt(0.83, 3.0 / 16) : Relaxation::bgk(0.83);
  AaSweepArgs a{&f, &force, &rho, &u, solid.data(), {2e-5, -0.0, -3e-5}, relax};
  if (kForce == ForceMode::kField) a.force_lo = lo.data(), a.force_hi = hi.data();
  a.j_begin = 0, a.j_end = kNy, a.k_begin = 0, a.k_end = kNz;

  // The reference: collide() cell by cell on copies, with the sweep's addressing.
  const grid::Field<double> f_before = f;
  grid::Field<double> f_ref = f, rho_ref = rho, u_ref = u;
  for (int k = 0; k < kNz; ++k)
    for (int j = 0; j < kNy; ++j)
      for (int i = 0; i < kNx; ++i) {
        const std::ptrdiff_t c = f.index(i, j, k);
        std::ptrdiff_t from[Q], to[Q];
        double in[Q], out[Q];
        for (int q = 0; q < Q; ++q) {
          const std::ptrdiff_t off =
              L::c[q][0] + L::c[q][1] * f.stride_y() + L::c[q][2] * f.stride_z();
          from[q] = kFromPost ? L::opp[q] * std::ptrdiff_t(f.plane_size()) + c - off
                              : q * std::ptrdiff_t(f.plane_size()) + c;
          to[q] = kFromPost ? q * std::ptrdiff_t(f.plane_size()) + c + off
                            : L::opp[q] * std::ptrdiff_t(f.plane_size()) + c;
          in[q] = out[q] = f.data()[from[q]];
        }
        const int r = j + kNy * k;
        const bool loads = kForce == ForceMode::kField && i >= lo[r] && i < hi[r];
        double g[3];
        for (int d = 0; d < 3; ++d)
          g[d] = kForce == ForceMode::kNone      ? 0.0
                 : kForce == ForceMode::kUniform ? a.uniform_force[d]
                 : loads                         ? a.uniform_force[d] + force(i, j, k, d)
                                                 : a.uniform_force[d] + 0.0;
        double m, ux, uy, uz;
        collide<L, kTrt>(out, relax, g[0], g[1], g[2], m, ux, uy, uz);
        const bool s = kSolids && solid[c];
        for (int q = 0; q < Q; ++q) f_ref.data()[to[q]] = s ? in[L::opp[q]] : out[q];
        if (kMacro && !s) {
          rho_ref(i, j, k) = m;
          u_ref(i, j, k, 0) = ux, u_ref(i, j, k, 1) = uy, u_ref(i, j, k, 2) = uz;
        }
      }
  aa_stream_collide<L, kTrt, kForce, kMacro, kSolids, kFromPost>(a);

  auto differing = [](const grid::Field<double>& x, const grid::Field<double>& y) {
    long n = 0;
    for (std::size_t i = 0; i < x.plane_size() * std::size_t(x.ncomp()); ++i)
      n += std::memcmp(&x.data()[i], &y.data()[i], sizeof(double)) != 0;
    return n;
  };
  EXPECT_EQ(differing(f, f_ref), 0) << L::name << " populations";
  EXPECT_EQ(differing(rho, rho_ref), 0) << L::name << " density";
  EXPECT_EQ(differing(u, u_ref), 0) << L::name << " velocity";
  // The comparison means something: the sweep changed most populations of the owned cells.
  EXPECT_GT(differing(f, f_before), long(Q) * kNx * kNy * kNz / 2);
}

template <class L, bool kTrt, ForceMode kForce>
void every_variant() {
  expect_bits_of_collide<L, kTrt, kForce, false, false, true>();
  expect_bits_of_collide<L, kTrt, kForce, false, false, false>();
  expect_bits_of_collide<L, kTrt, kForce, true, true, true>();
  expect_bits_of_collide<L, kTrt, kForce, true, true, false>();
  expect_bits_of_collide<L, kTrt, kForce, true, false, false>();
  expect_bits_of_collide<L, kTrt, kForce, false, true, true>();
}

}  // namespace

TEST(AaSweepBits, D3Q15) {
  every_variant<D3Q15, false, ForceMode::kNone>();
  every_variant<D3Q15, true, ForceMode::kUniform>();
  every_variant<D3Q15, false, ForceMode::kField>();
  every_variant<D3Q15, true, ForceMode::kField>();
}

TEST(AaSweepBits, D3Q19) {
  every_variant<D3Q19, true, ForceMode::kNone>();
  every_variant<D3Q19, false, ForceMode::kUniform>();
  every_variant<D3Q19, false, ForceMode::kField>();
  every_variant<D3Q19, true, ForceMode::kField>();
}
