#include "models/plants/seaweed_body_forces.hpp"

#include <cmath>
#include <cstring>

namespace biota::models::plants {

namespace {

constexpr int B = 8;

/// One sphere's force on axis d from its position, velocity and drag on that axis (scalars or
/// lane values; the same operations either way). std::max(0.0, a) and std::min(0.0, a) as
/// selects; a periodic axis has its limits at infinity, so no wall acts.
inline Real axis_force(const BodyForceLaw& law, int d, Real weight, Real drag, Real x, Real v) {
  const Real f = weight + drag;
  const Real lo = law.wall_lo[d] - x, hi = x - law.wall_hi[d];
  const Real push = law.contact_k * lo - law.contact_c * v;
  const Real pull = -law.contact_k * hi - law.contact_c * v;
  Real fw = 0;
  fw = lo > 0 ? (0.0 < push ? push : 0.0) : fw;
  fw = hi > 0 ? (pull < 0.0 ? pull : 0.0) : fw;
  // Adding +0 where no wall touches is exact: f is never -0 (weight + drag, weight +0 or not 0).
  return f + fw;
}

/// The drag factor 0.5 C_d rho A |u - v| (times the relative velocity per axis).
inline Real drag_factor(const BodyForceLaw& law, Real rx, Real ry, Real rz) {
  return law.drag_coef * std::sqrt(rx * rx + ry * ry + rz * rz);
}

}  // namespace

void body_forces(const BodyForceLaw& law, const BodyForceColumns& c, std::size_t n) {
  std::size_t i0 = 0;
  for (; i0 + B <= n; i0 += B) {
    Real x[B], y[B], z[B], vx[B], vy[B], vz[B], ux[B], uy[B], uz[B];
    Real fx[B], fy[B], fz[B], ix[B], iy[B], iz[B];
    const auto in = [&](Real* lane, const Real* col) { std::memcpy(lane, col + i0, sizeof(x)); };
    in(x, c.x[0]), in(y, c.x[1]), in(z, c.x[2]), in(vx, c.v[0]), in(vy, c.v[1]), in(vz, c.v[2]);
    in(ux, c.u_fluid[0]), in(uy, c.u_fluid[1]), in(uz, c.u_fluid[2]);
    for (int l = 0; l < B; ++l) {
      const Real rx = ux[l] - vx[l], ry = uy[l] - vy[l], rz = uz[l] - vz[l];
      const Real s = drag_factor(law, rx, ry, rz);
      const Real dx = rx * s, dy = ry * s, dz = rz * s;
      fx[l] = axis_force(law, 0, 0.0, dx, x[l], vx[l]);
      fy[l] = axis_force(law, 1, 0.0, dy, y[l], vy[l]);
      fz[l] = axis_force(law, 2, law.weight_z, dz, z[l], vz[l]);
      ix[l] = dx * law.dt, iy[l] = dy * law.dt, iz[l] = dz * law.dt;
    }
    const Real* f[3] = {fx, fy, fz};
    const Real* imp[3] = {ix, iy, iz};
    for (int d = 0; d < 3; ++d) {
      std::memcpy(c.force[d] + i0, f[d], sizeof(x));
      std::memset(c.torque[d] + i0, 0, sizeof(x));
      for (int l = 0; l < B; ++l) c.impulse[d][i0 + l] += imp[d][l];
    }
  }
  for (std::size_t i = i0; i < n; ++i) {
    const Real vx = c.v[0][i], vy = c.v[1][i], vz = c.v[2][i];
    const Real rx = c.u_fluid[0][i] - vx, ry = c.u_fluid[1][i] - vy, rz = c.u_fluid[2][i] - vz;
    const Real s = drag_factor(law, rx, ry, rz);
    const Real dx = rx * s, dy = ry * s, dz = rz * s;
    c.force[0][i] = axis_force(law, 0, 0.0, dx, c.x[0][i], vx);
    c.force[1][i] = axis_force(law, 1, 0.0, dy, c.x[1][i], vy);
    c.force[2][i] = axis_force(law, 2, law.weight_z, dz, c.x[2][i], vz);
    for (int d = 0; d < 3; ++d) c.torque[d][i] = 0;
    c.impulse[0][i] += dx * law.dt, c.impulse[1][i] += dy * law.dt, c.impulse[2][i] += dz * law.dt;
  }
}

}  // namespace biota::models::plants
