#include "models/plants/seaweed_joint_block.hpp"

#include <cmath>

namespace biota::models::plants {

namespace {

constexpr int B = kJointBlock;
using V = JointBlock::V;
using Q = JointBlock::Q;

/// core::Quat::rotate per lane: t = 2 cross(u, v); v + w t + cross(u, t).
inline void rotate(const Q& q, const V& v, V& o) {
  for (int l = 0; l < B; ++l) {
    const Real tx = (q.y[l] * v.z[l] - q.z[l] * v.y[l]) * 2.0;
    const Real ty = (q.z[l] * v.x[l] - q.x[l] * v.z[l]) * 2.0;
    const Real tz = (q.x[l] * v.y[l] - q.y[l] * v.x[l]) * 2.0;
    o.x[l] = (v.x[l] + tx * q.w[l]) + (q.y[l] * tz - q.z[l] * ty);
    o.y[l] = (v.y[l] + ty * q.w[l]) + (q.z[l] * tx - q.x[l] * tz);
    o.z[l] = (v.z[l] + tz * q.w[l]) + (q.x[l] * ty - q.y[l] * tx);
  }
}

/// a * b of core::Quat per lane (the operands as given, conjugation done by the caller).
inline void mul(const Q& a, const Q& b, Q& o) {
  for (int l = 0; l < B; ++l) {
    o.w[l] = a.w[l] * b.w[l] - a.x[l] * b.x[l] - a.y[l] * b.y[l] - a.z[l] * b.z[l];
    o.x[l] = a.w[l] * b.x[l] + a.x[l] * b.w[l] + a.y[l] * b.z[l] - a.z[l] * b.y[l];
    o.y[l] = a.w[l] * b.y[l] - a.x[l] * b.z[l] + a.y[l] * b.w[l] + a.z[l] * b.x[l];
    o.z[l] = a.w[l] * b.z[l] + a.x[l] * b.y[l] - a.y[l] * b.x[l] + a.z[l] * b.w[l];
  }
}

inline void conj(const Q& a, Q& o) {
  for (int l = 0; l < B; ++l) o.w[l] = a.w[l], o.x[l] = -a.x[l], o.y[l] = -a.y[l], o.z[l] = -a.z[l];
}

/// o = cross(a, b) + s * c (s = +1 or -1 as an exact add or subtract of c).
inline void cross_add(const V& a, const V& b, const V& c, bool subtract, V& o) {
  for (int l = 0; l < B; ++l) {
    const Real x = a.y[l] * b.z[l] - a.z[l] * b.y[l];
    const Real y = a.z[l] * b.x[l] - a.x[l] * b.z[l];
    const Real z = a.x[l] * b.y[l] - a.y[l] * b.x[l];
    o.x[l] = subtract ? x - c.x[l] : x + c.x[l];
    o.y[l] = subtract ? y - c.y[l] : y + c.y[l];
    o.z[l] = subtract ? z - c.z[l] : z + c.z[l];
  }
}

/// atan(z) / z from z2 = z^2 < 0.01: the alternating series to z^16 (first dropped term below
/// 1e-19).
inline Real atan_over_z(Real z2) {
  return 1 +
         z2 * (-1.0 / 3 +
               z2 * (1.0 / 5 +
                     z2 * (-1.0 / 7 +
                           z2 * (1.0 / 9 + z2 * (-1.0 / 11 +
                                                 z2 * (1.0 / 13 + z2 * (-1.0 / 15 + z2 / 17)))))));
}

}  // namespace

void evaluate_joint_block(JointBlock& b, Real joint_k, Real joint_c, Real bend_k, Real bend_c) {
  // The parent's anchor 0 - ac: what (x - x_parent) / 2 was at build, bit for bit, as the
  // child's was (x_parent - x) / 2 (a - b = -(b - a) exactly, and 0 - (+0) = +0).
  V ap, rc, rp;
  for (int l = 0; l < B; ++l)
    ap.x[l] = 0.0 - b.ac.x[l], ap.y[l] = 0.0 - b.ac.y[l], ap.z[l] = 0.0 - b.ac.z[l];
  rotate(b.qc, b.ac, rc);
  rotate(b.qp, ap, rp);
  // Stretch spring-damper at the anchor: F = gap k + (v_p - v_c) c on the child, with the anchor
  // velocities v + cross(w, r) and gap = (x_p + r_p) - (x_c + r_c).
  for (int l = 0; l < B; ++l) {
    const Real vcx = b.vc.x[l] + (b.wc.y[l] * rc.z[l] - b.wc.z[l] * rc.y[l]);
    const Real vcy = b.vc.y[l] + (b.wc.z[l] * rc.x[l] - b.wc.x[l] * rc.z[l]);
    const Real vcz = b.vc.z[l] + (b.wc.x[l] * rc.y[l] - b.wc.y[l] * rc.x[l]);
    const Real vpx = b.vp.x[l] + (b.wp.y[l] * rp.z[l] - b.wp.z[l] * rp.y[l]);
    const Real vpy = b.vp.y[l] + (b.wp.z[l] * rp.x[l] - b.wp.x[l] * rp.z[l]);
    const Real vpz = b.vp.z[l] + (b.wp.x[l] * rp.y[l] - b.wp.y[l] * rp.x[l]);
    const Real gx = (b.xp.x[l] + rp.x[l]) - (b.xc.x[l] + rc.x[l]);
    const Real gy = (b.xp.y[l] + rp.y[l]) - (b.xc.y[l] + rc.y[l]);
    const Real gz = (b.xp.z[l] + rp.z[l]) - (b.xc.z[l] + rc.z[l]);
    b.F.x[l] = gx * joint_k + (vpx - vcx) * joint_c;
    b.F.y[l] = gy * joint_k + (vpy - vcy) * joint_c;
    b.F.z[l] = gz * joint_k + (vpz - vcz) * joint_c;
  }
  // Relative rotation q_p^* q_c (the rest relative orientation is the identity) and its rotation
  // vector (Quat::rotation_vector: the hemisphere w >= 0, angle 2 atan2(s, w), axis * angle; the
  // small-angle branch 2 (x, y, z)).
  Q cp, rel;
  conj(b.qp, cp);
  mul(cp, b.qc, rel);
  // The hemisphere flip as selects and sqrt without errno (this file is built with
  // -fno-math-errno), so both loops vectorise.
  Real s[B];
  for (int l = 0; l < B; ++l) {
    const bool flip = rel.w[l] < 0;
    rel.w[l] = flip ? -rel.w[l] : rel.w[l], rel.x[l] = flip ? -rel.x[l] : rel.x[l];
    rel.y[l] = flip ? -rel.y[l] : rel.y[l], rel.z[l] = flip ? -rel.z[l] : rel.z[l];
    s[l] = std::sqrt(rel.x[l] * rel.x[l] + rel.y[l] * rel.y[l] + rel.z[l] * rel.z[l]);
  }
  // f = 2 atan2(s, w) / s = (2 / w) atan(z) / z with z = s / w. Below z^2 = 0.01 (a bend of
  // 11 degrees) atan(z) / z is its alternating series to z^16 (first dropped term < 1e-19):
  // 2 atan2(s, w) to round-off without libm's atan2 (3.5% of a seaweed cycle-5 profile). Larger
  // bends: libm, lane by lane after the vector pass. Below s = 1e-12 the rotation vector is
  // 2 (x, y, z), i.e. f = 2.
  Real f[B], z2[B];
  for (int l = 0; l < B; ++l) {
    const Real inv_w = 1 / rel.w[l];
    z2[l] = s[l] * s[l] * inv_w * inv_w;
    const Real p = atan_over_z(z2[l]);
    f[l] = s[l] < 1e-12 ? 2.0 : 2 * inv_w * p;
  }
  // Bends of 11 to 90 degrees (z^2 from 0.01 to 1): three half-angle steps, atan2(s, w) =
  // 2 atan2(s, w + sqrt(w^2 + s^2)), bring z below 0.0985 (z^2 < 0.0097), where the series
  // holds; vector lanes for the whole block when any lane needs it. Beyond 90 degrees: libm.
  const auto mid_bend = [&](int l) { return s[l] >= 1e-12 && !(z2[l] < 0.01) && z2[l] < 1; };
  int mid = 0;
  for (int l = 0; l < B; ++l) mid += mid_bend(l);
  if (mid > 0) {
    Real fh[B];
    for (int l = 0; l < B; ++l) {
      const Real s2 = s[l] * s[l];
      Real wh = rel.w[l];
      wh = wh + std::sqrt(wh * wh + s2);
      wh = wh + std::sqrt(wh * wh + s2);
      wh = wh + std::sqrt(wh * wh + s2);
      const Real inv_w = 1 / wh, z = s2 * inv_w * inv_w;
      const Real p = atan_over_z(z);
      fh[l] = 16 * inv_w * p;
    }
    for (int l = 0; l < B; ++l)
      if (mid_bend(l)) f[l] = fh[l];
  }
  for (int l = 0; l < B; ++l)
    if (s[l] >= 1e-12 && !(z2[l] < 1)) f[l] = (2 * std::atan2(s[l], rel.w[l])) / s[l];
  V rv;
  for (int l = 0; l < B; ++l)
    rv.x[l] = rel.x[l] * f[l], rv.y[l] = rel.y[l] * f[l], rv.z[l] = rel.z[l] * f[l];
  V theta;
  rotate(b.qp, rv, theta);
  // T = theta (-k_b) - (w_c - w_p) c_b on the child.
  const Real nk = -bend_k;
  for (int l = 0; l < B; ++l) {
    b.T.x[l] = theta.x[l] * nk - (b.wc.x[l] - b.wp.x[l]) * bend_c;
    b.T.y[l] = theta.y[l] * nk - (b.wc.y[l] - b.wp.y[l]) * bend_c;
    b.T.z[l] = theta.z[l] * nk - (b.wc.z[l] - b.wp.z[l]) * bend_c;
  }
  V mF;
  for (int l = 0; l < B; ++l) mF.x[l] = -b.F.x[l], mF.y[l] = -b.F.y[l], mF.z[l] = -b.F.z[l];
  cross_add(rc, b.F, b.T, false, b.tc);
  cross_add(rp, mF, b.T, true, b.tp);
  for (int l = 0; l < B; ++l) {
    b.fm[l] = std::sqrt(b.F.x[l] * b.F.x[l] + b.F.y[l] * b.F.y[l] + b.F.z[l] * b.F.z[l]);
    b.tm[l] = std::sqrt(b.T.x[l] * b.T.x[l] + b.T.y[l] * b.T.y[l] + b.T.z[l] * b.T.z[l]);
  }
}

}  // namespace biota::models::plants
