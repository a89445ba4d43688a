#pragma once
/// \file seaweed_contact_law.hpp
/// \brief The seaweed sphere-sphere contact law (paper section 4): a normal spring-damper on the
/// overlap and viscous friction capped by Coulomb's law, with the contact point's velocities
/// from the spheres' spins. Evaluated for the pair in a fixed orientation (lower global id
/// first), so both owners of a pair get the same bits. One definition for scalar and vector
/// use: written without branches, so a loop of lanes over it vectorises (seaweed_contact_block).
#include <cmath>

#include "core/types.hpp"

namespace biota::models::plants {

using core::Real;
using core::Vec3;

/// \brief What the contact law and a joint's parent read of a sphere, in one record of two whole
/// cache lines: position, velocity, angular velocity, radius and orientation (w, x, y, z).
struct alignas(64) SphereHot {
  Vec3 x, v, w;
  Real r, q[4], pad[2];
};

/// \brief Contact law coefficients (MechanicsParams: contact_k, contact_c, friction, friction_c).
struct ContactLaw {
  Real k, c, mu, mu_c;
};

/// \brief Whether two spheres at squared centre distance d2 with radii summing to rr are clearly
/// apart: the law's first test, with a margin far above round-off. Symmetric in the pair (d2 and
/// rr are the same bits either way round), so the inner-list filter and the compaction of
/// touching contacts apply it from the owned sphere's side.
inline bool clearly_apart(Real d2, Real rr) {
  return d2 > rr * rr * (1 + 1e-9);
}

/// \brief The law for the pair (a, b), a the lower global id, without branches (vector lanes):
/// the force F on a (b gets -F) and the torques on a (t0) and on b (t1); `touch` is false when the
/// two do not touch, and the caller then adds nothing (the other outputs are then meaningless,
/// possibly NaN). std::max(0, .) and std::min(., .) are written as the selects they are.
inline void contact_law(const Vec3& xa, const Vec3& va, const Vec3& wa, Real ra, const Vec3& xb,
                        const Vec3& vb, const Vec3& wb, Real rb, const ContactLaw& law, bool& touch,
                        Vec3& F, Vec3& t0, Vec3& t1) {
  const Vec3 d = xa - xb;
  const Real d2 = core::dot(d, d);
  const Real dist = std::sqrt(d2);
  const Real overlap = ra + rb - dist;
  touch = !(clearly_apart(d2, ra + rb) | (overlap <= 0) | (dist <= 0));
  const Vec3 n = d / dist;
  const Vec3 vrel = (va + core::cross(wa, n * (-ra))) - (vb + core::cross(wb, n * rb));
  const Real vn = core::dot(vrel, n);
  const Real fn_raw = law.k * overlap - law.c * vn;
  const Real fn = 0.0 < fn_raw ? fn_raw : 0.0;
  const Vec3 vt = vrel - n * vn;
  const Real vtn = std::sqrt(core::dot(vt, vt));
  // Viscous friction capped by Coulomb: -min(mu_c |v_t|, mu f_n) v_t / |v_t|.
  const Real slip = law.mu_c * vtn, cap = law.mu * fn;
  const Real s = -(cap < slip ? cap : slip) / vtn;
  const bool sliding = vtn > 0;
  const Vec3 ft{sliding ? vt.x * s : 0.0, sliding ? vt.y * s : 0.0, sliding ? vt.z * s : 0.0};
  F = n * fn + ft;
  t0 = core::cross(n * (-ra), ft), t1 = core::cross(n * rb, -ft);
}

}  // namespace biota::models::plants
