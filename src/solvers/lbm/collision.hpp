#pragma once
/// \file collision.hpp
/// \brief Pointwise collision kernels: equilibrium, BGK and TRT with Guo forcing.
///
/// Pure functions of one cell's populations (AMReX *_K.H style), unit-tested alone.
/// Lattice units, c_s^2 = 1/3.
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
inline double equilibrium(int i, double rho, double ux, double uy, double uz) {
  const double cu = L::c[i][0] * ux + L::c[i][1] * uy + L::c[i][2] * uz;
  const double uu = ux * ux + uy * uy + uz * uz;
  return L::w[i] * rho * (1.0 + 3.0 * cu + 4.5 * cu * cu - 1.5 * uu);
}

/// \brief Collide one cell in place: f holds the streamed populations on entry and the
/// post-collision ones on exit. `trt` selects TRT (else BGK with omega_plus). Guo forcing with
/// force density (fx, fy, fz): u = (sum c f + F/2)/rho and source
/// S_i = w_i [3(c_i - u) + 9 (c_i.u) c_i].F (Guo, Zheng & Shi 2002, eq. 20).
/// Returns the density and physical velocity through rho, u*.
template <class L, bool kTrt>
inline void collide(double* f, const Relaxation& r, double fx, double fy, double fz, double& rho,
                    double& ux, double& uy, double& uz) {
  constexpr int Q = L::Q;
  double m0 = 0, jx = 0, jy = 0, jz = 0;
  // The Q-loops are unrolled completely (#pragma GCC unroll) so that the caller's cell loop is
  // vectorised: GCC 12 does not vectorise a loop nest with several consecutive inner loops
  // (docs/performance-lbm-layout.md). Same operations in the same order, so same bits.
#pragma GCC unroll 32
  for (int i = 0; i < Q; ++i) {
    m0 += f[i];
    jx += L::c[i][0] * f[i];
    jy += L::c[i][1] * f[i];
    jz += L::c[i][2] * f[i];
  }
  rho = m0;
  const double inv_rho = 1.0 / rho;
  ux = (jx + 0.5 * fx) * inv_rho;
  uy = (jy + 0.5 * fy) * inv_rho;
  uz = (jz + 0.5 * fz) * inv_rho;
  const double uu = ux * ux + uy * uy + uz * uz;
  const double uf = ux * fx + uy * fy + uz * fz;
  double feq[Q], src[Q];
#pragma GCC unroll 32
  for (int i = 0; i < Q; ++i) {
    const double cu = L::c[i][0] * ux + L::c[i][1] * uy + L::c[i][2] * uz;
    const double cf = L::c[i][0] * fx + L::c[i][1] * fy + L::c[i][2] * fz;
    feq[i] = L::w[i] * rho * (1.0 + 3.0 * cu + 4.5 * cu * cu - 1.5 * uu);
    src[i] = L::w[i] * (3.0 * (cf - uf) + 9.0 * cu * cf);
  }
  if constexpr (!kTrt) {
    const double om = r.omega_plus, keep = 1.0 - om, sf = 1.0 - 0.5 * om;
#pragma GCC unroll 32
    for (int i = 0; i < Q; ++i) f[i] = keep * f[i] + om * feq[i] + sf * src[i];
  } else {
    const double op = r.omega_plus, om = r.omega_minus;
    const double sp = 1.0 - 0.5 * op, sm = 1.0 - 0.5 * om;
    f[0] = f[0] - op * (f[0] - feq[0]) + sp * src[0];
#pragma GCC unroll 32
    for (int i = 1; i < Q; i += 2) {  // opposite pairs are (i, i+1) in both descriptors
      const int j = i + 1;
      const double fp = 0.5 * (f[i] + f[j]), fm = 0.5 * (f[i] - f[j]);
      const double ep = 0.5 * (feq[i] + feq[j]), em = 0.5 * (feq[i] - feq[j]);
      const double qp = 0.5 * (src[i] + src[j]), qm = 0.5 * (src[i] - src[j]);
      const double dp = -op * (fp - ep) + sp * qp, dm = -om * (fm - em) + sm * qm;
      f[i] += dp + dm;
      f[j] += dp - dm;
    }
  }
}

}  // namespace biota::solvers::lbm
