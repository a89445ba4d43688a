#include "models/plants/seaweed_integrate.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/quat.hpp"

namespace biota::models::plants {

namespace {

/// One sphere, scalar: the step as SeaweedBodies wrote it.
inline void integrate_one(const SphereColumns& c, std::size_t i, Real h, Real h_over_m,
                          Real h_over_i) {
  const Real vx = c.vx[i] + c.fx[i] * h_over_m, vy = c.vy[i] + c.fy[i] * h_over_m,
             vz = c.vz[i] + c.fz[i] * h_over_m;
  const Real wx = c.wx[i] + c.tx[i] * h_over_i, wy = c.wy[i] + c.ty[i] * h_over_i,
             wz = c.wz[i] + c.tz[i] * h_over_i;
  c.vx[i] = vx, c.vy[i] = vy, c.vz[i] = vz;
  c.wx[i] = wx, c.wy[i] = wy, c.wz[i] = wz;
  c.px[i] = c.px[i] + vx * h, c.py[i] = c.py[i] + vy * h, c.pz[i] = c.pz[i] + vz * h;
  const core::Quat q = core::Quat{c.qw[i], c.qx[i], c.qy[i], c.qz[i]}.integrated({wx, wy, wz}, h);
  c.qw[i] = q.w, c.qx[i] = q.x, c.qy[i] = q.y, c.qz[i] = q.z;
}

}  // namespace

void integrate_spheres(const SphereColumns& c, std::size_t n, Real h, Real h_over_m,
                       Real h_over_i) {
  constexpr int B = 8;
  using Lane = Real[B];
  std::size_t i0 = 0;
  for (; i0 + B <= n; i0 += B) {
    // The block's columns into lanes (64-byte copies), the step on whole lanes, and back.
    Lane fx, fy, fz, tx, ty, tz, vx, vy, vz, wx, wy, wz, px, py, pz, qw, qx, qy, qz;
    const auto in = [&](Real* lane, const Real* col) { std::memcpy(lane, col + i0, sizeof(Lane)); };
    const auto out = [&](Real* col, const Real* lane) {
      std::memcpy(col + i0, lane, sizeof(Lane));
    };
    in(fx, c.fx), in(fy, c.fy), in(fz, c.fz), in(tx, c.tx), in(ty, c.ty), in(tz, c.tz);
    in(vx, c.vx), in(vy, c.vy), in(vz, c.vz), in(wx, c.wx), in(wy, c.wy), in(wz, c.wz);
    in(px, c.px), in(py, c.py), in(pz, c.pz);
    in(qw, c.qw), in(qx, c.qx), in(qy, c.qy), in(qz, c.qz);
    // Quat::integrated for a half-angle below 0.01 (its series), on all lanes; lanes beyond
    // keep their orientation here and take the scalar map after. (Masks as doubles and bitwise
    // logic: GCC 12 vectorises neither 1-byte lanes beside 8-byte ones nor && / ||.)
    Lane large;
    for (int l = 0; l < B; ++l) {
      vx[l] = vx[l] + fx[l] * h_over_m, vy[l] = vy[l] + fy[l] * h_over_m;
      vz[l] = vz[l] + fz[l] * h_over_m;
      wx[l] = wx[l] + tx[l] * h_over_i, wy[l] = wy[l] + ty[l] * h_over_i;
      wz[l] = wz[l] + tz[l] * h_over_i;
      px[l] = px[l] + vx[l] * h, py[l] = py[l] + vy[l] * h, pz[l] = pz[l] + vz[l] * h;
      const Real w2 = wx[l] * wx[l] + wy[l] * wy[l] + wz[l] * wz[l];
      const bool still = w2 * h * h < 1e-30;
      const Real t2 = 0.25 * w2 * h * h;
      const bool is_large = !still & !(t2 < 1e-4);
      large[l] = is_large ? 1.0 : 0.0;
      Real cw, sw;
      core::Quat::small_rotation(t2, h, cw, sw);
      const core::Quat q0{qw[l], qx[l], qy[l], qz[l]};
      const core::Quat q1 = q0.rotated(cw, {wx[l], wy[l], wz[l]}, sw);
      const bool keep = still | is_large;
      qw[l] = keep ? q0.w : q1.w, qx[l] = keep ? q0.x : q1.x;
      qy[l] = keep ? q0.y : q1.y, qz[l] = keep ? q0.z : q1.z;
    }
    for (int l = 0; l < B; ++l)
      if (large[l] != 0) {
        const core::Quat q =
            core::Quat{qw[l], qx[l], qy[l], qz[l]}.integrated({wx[l], wy[l], wz[l]}, h);
        qw[l] = q.w, qx[l] = q.x, qy[l] = q.y, qz[l] = q.z;
      }
    out(c.vx, vx), out(c.vy, vy), out(c.vz, vz), out(c.wx, wx), out(c.wy, wy), out(c.wz, wz);
    out(c.px, px), out(c.py, py), out(c.pz, pz);
    out(c.qw, qw), out(c.qx, qx), out(c.qy, qy), out(c.qz, qz);
  }
  for (; i0 < n; ++i0) integrate_one(c, i0, h, h_over_m, h_over_i);
}

}  // namespace biota::models::plants
