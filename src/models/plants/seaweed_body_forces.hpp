#pragma once
/// \file seaweed_body_forces.hpp
/// \brief The forces on a seaweed sphere that need no partner: weight and buoyancy (eq. 9 plus
/// gravity), quadratic drag with the relative velocity (eq. 10) and the tank walls (the contact
/// spring). Lanes of 8 spheres run as vector instructions with exactly the scalar operations
/// (the build uses -ffp-contract=off), so the bits are those of a sphere-by-sphere loop.
#include <cstddef>

#include "core/types.hpp"

namespace biota::models::plants {

using core::Real;

struct BodyForceLaw {
  Real weight_z;   ///< (rho_water - rho_plant) V g [N] (the weight's x and y are 0)
  Real drag_coef;  ///< 0.5 C_d rho_water A [kg/m]
  Real dt;         ///< sub-step, for the drag impulse [s]
  Real contact_k, contact_c;
  Real wall_lo[3], wall_hi[3];  ///< sphere centre limits [m]; -inf and +inf on periodic axes
};

/// \brief Columns read and written (x, y, z components).
struct BodyForceColumns {
  const Real *x[3], *v[3], *u_fluid[3];
  Real *force[3], *torque[3], *impulse[3];
};

/// \brief For spheres [0, n): force = weight + drag + walls, torque = 0, impulse += drag dt.
void body_forces(const BodyForceLaw& law, const BodyForceColumns& c, std::size_t n);

}  // namespace biota::models::plants
