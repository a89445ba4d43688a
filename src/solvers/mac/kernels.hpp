#pragma once
/// \file kernels.hpp
/// \brief Pointwise kernels of the MAC solver: pure functions, unit-tested alone.
#include <cmath>

#include "core/types.hpp"

namespace biota::solvers::mac {

using core::Real;

/// \brief a * du/dx times 2 dx by second-order upwinding (Warming & Beam one-sided 3-point
/// difference on the side the velocity `a` comes from). The advective term of eq. (13),
/// -(v . grad) v, is the sum over axes of -upwind2(...) / (2 dx). Truncation error O(dx^2).
inline Real upwind2(Real a, Real um2, Real um1, Real u0, Real up1, Real up2) {
  return a > 0 ? a * (3 * u0 - 4 * um1 + um2) : a * (-3 * u0 + 4 * up1 - up2);
}

/// \brief Neutral atmospheric surface-layer (logarithmic) profile: U(z) = U_ref ln(z/z0) /
/// ln(z_ref/z0), zero at and below the roughness length z0.
inline Real log_profile(Real z, Real u_ref, Real z_ref, Real z0) {
  if (z <= z0) return 0;
  return u_ref * std::log(z / z0) / std::log(z_ref / z0);
}

/// \brief Drag coefficient of a rough wall from the log law, C = (kappa / ln(z1/z0))^2, so that
/// the wall shear stress per unit mass is tau = C |U_1| U_1 with U_1 the tangential velocity at
/// height z1 (the first cell centre). kappa = 0.41 (von Karman).
inline Real wall_drag_coefficient(Real z1, Real z0) {
  const Real k = 0.41 / std::log(z1 / z0);
  return k * k;
}

}  // namespace biota::solvers::mac
