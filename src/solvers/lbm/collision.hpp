#pragma once
/// \file collision.hpp
/// \brief Pointwise collision kernels: equilibrium, BGK and TRT with Guo forcing.
///
/// Pure functions of one cell's populations (AMReX *_K.H style), unit-tested alone.
/// Lattice units, c_s^2 = 1/3.
#include <array>
#include <cmath>

#include "solvers/lbm/lattice.hpp"

namespace biota::solvers::lbm {

/// \brief Relaxation rates. BGK uses omega_plus only; TRT: omega_minus from the magic parameter
/// Lambda = (1/omega_plus - 1/2)(1/omega_minus - 1/2) (Ginzburg 2008).
struct Relaxation {
  double omega_plus = 1.0;
  double omega_minus = 1.0;
  static Relaxation bgk(double tau) { return {1.0 / tau, 1.0 / tau}; }
  static Relaxation trt(double tau, double magic) {
    const double tau_minus = magic / (tau - 0.5) + 0.5;
    return {1.0 / tau, 1.0 / tau_minus};
  }
};

/// \brief Second-order equilibrium f_i^eq(rho, u) (seaweed paper eq. 13).
template <class L>
[[gnu::always_inline]] inline double equilibrium(int i, double rho, double ux, double uy,
                                                 double uz) {
  const double cu = L::c[i][0] * ux + L::c[i][1] * uy + L::c[i][2] * uz;
  const double uu = ux * ux + uy * uy + uz * uz;
  return L::w[i] * rho * (1.0 + 3.0 * cu + 4.5 * cu * cu - 1.5 * uu);
}

/// \brief c . v adding only the non-zero components of c (a product with 0.0 cannot be folded
/// away under IEEE rules). Called with c known once the caller's loop is unrolled.
[[gnu::always_inline]] inline double cdot(const std::array<int, 3>& c, double x, double y,
                                          double z) {
  double s = 0.0;
  bool any = false;
  const double v[3] = {x, y, z};
  for (int a = 0; a < 3; ++a) {
    if (c[a] == 0) continue;
    s = any ? (c[a] > 0 ? s + v[a] : s - v[a]) : (c[a] > 0 ? v[a] : -v[a]);
    any = true;
  }
  return s;
}

/// \brief Collide one cell in place: f holds the streamed populations on entry and the
/// post-collision ones on exit. `kTrt` selects TRT (else BGK with omega_plus). Guo forcing with
/// force density (fx, fy, fz): u = (sum c f + F/2)/rho and source
/// S_i = w_i [3(c_i - u) + 9 (c_i.u) c_i].F (Guo, Zheng & Shi 2002, eq. 20).
/// Returns the density and physical velocity through rho, u*.
///
/// Written on opposite pairs (i, i+1): with s = f_i + f_i+1 and d = f_i - f_i+1 the moments are
/// sums of s and signed d, and the even (symmetric) and odd parts of equilibrium and source give
/// per pair dp = w [A + cu (B cu + C cf)] - om+/2 s and dm = w [B' cu + C' cf] - om-/2 d, then
/// f_i += dp + dm, f_i+1 += dp - dm. BGK is the same with om- = om+. One reciprocal per cell,
/// no other division, per-cell factors hoisted, explicit fma (deterministic: not left to
/// contraction, so every code path gives the same bits). Always inlined: GCC 12 tuning for a CPU
/// it does not know (Zen 5) left it an out-of-line call per cell, and D3Q15 ran 3-4x slower.
template <class L, bool kTrt>
[[gnu::always_inline]] inline void collide(double* f, const Relaxation& r, double fx, double fy,
                                           double fz, double& rho, double& ux, double& uy,
                                           double& uz) {
  constexpr int P = (L::Q - 1) / 2;  // opposite pairs (2p+1, 2p+2)
  double s[P], d[P];
  double m = f[0], jx = 0, jy = 0, jz = 0;
  // Unrolled completely (#pragma GCC unroll) so that the lattice constants fold and the caller's
  // cell loop vectorises (GCC 12 does not vectorise a nest of several inner loops).
#pragma GCC unroll 32
  for (int p = 0; p < P; ++p) {
    const int q = 2 * p + 1;
    s[p] = f[q] + f[q + 1];
    d[p] = f[q] - f[q + 1];
    m += s[p];
    if (L::c[q][0] != 0) jx = L::c[q][0] > 0 ? jx + d[p] : jx - d[p];
    if (L::c[q][1] != 0) jy = L::c[q][1] > 0 ? jy + d[p] : jy - d[p];
    if (L::c[q][2] != 0) jz = L::c[q][2] > 0 ? jz + d[p] : jz - d[p];
  }
  rho = m;
  const double inv_rho = 1.0 / m;
  ux = (jx + 0.5 * fx) * inv_rho;
  uy = (jy + 0.5 * fy) * inv_rho;
  uz = (jz + 0.5 * fz) * inv_rho;
  const double uu = ux * ux + uy * uy + uz * uz;
  const double uf = ux * fx + uy * fy + uz * fz;
  const double op = r.omega_plus, om = kTrt ? r.omega_minus : r.omega_plus;
  const double sp = 1.0 - 0.5 * op, sm = 1.0 - 0.5 * om;
  const double a = std::fma(op * m, 1.0 - 1.5 * uu, -3.0 * sp * uf);
  const double b = 4.5 * op * m, cc = 9.0 * sp, bm = 3.0 * om * m, cm = 3.0 * sm;
  const double hp = 0.5 * op, hm = 0.5 * om;
  f[0] = std::fma(-op, f[0], std::fma(L::w[0], a, f[0]));
#pragma GCC unroll 32
  for (int p = 0; p < P; ++p) {
    const int q = 2 * p + 1;
    const double w = L::w[q];
    const double cu = cdot(L::c[q], ux, uy, uz);
    const double cf = cdot(L::c[q], fx, fy, fz);
    const double even = w * std::fma(cu, std::fma(b, cu, cc * cf), a);
    const double odd = w * std::fma(bm, cu, cm * cf);
    const double dp = std::fma(-hp, s[p], even), dm = std::fma(-hm, d[p], odd);
    f[q] += dp + dm;
    f[q + 1] += dp - dm;
  }
}

}  // namespace biota::solvers::lbm
