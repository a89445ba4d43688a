#pragma once
/// \file seaweed_integrate.hpp
/// \brief The seaweed spheres' symplectic Euler step over columns: velocities from the forces
/// first, then positions with the new velocities, orientations by core::Quat::integrated. Lanes
/// of 8 spheres at a time run as vector instructions; every lane performs exactly the scalar
/// operations in the same order (the build uses -ffp-contract=off), and rotations whose
/// half-angle is 0.01 or more take Quat::integrated itself, so the bits are the scalar code's.
#include <cstddef>

#include "core/types.hpp"

namespace biota::models::plants {

using core::Real;

/// \brief Columns of the sphere state the step reads and writes (x, y, z; quaternion w, x, y, z).
struct SphereColumns {
  const Real *fx, *fy, *fz, *tx, *ty, *tz;
  Real *vx, *vy, *vz, *wx, *wy, *wz, *px, *py, *pz, *qw, *qx, *qy, *qz;
};

/// \brief Advance spheres [0, n) by `h`: v += f h/m, w += t h/I, x += v h, q = q.integrated(w, h).
void integrate_spheres(const SphereColumns& c, std::size_t n, Real h, Real h_over_m, Real h_over_i);

}  // namespace biota::models::plants
