#pragma once
/// \file seaweed_contact_law.hpp
/// \brief The seaweed sphere-sphere contact law (paper section 4): a normal spring-damper on the
/// overlap and viscous friction capped by Coulomb's law, with the contact point's velocities
/// from the spheres' spins. Evaluated for the pair in a fixed orientation (lower global id
/// first), so both owners of a pair get the same bits.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/types.hpp"

namespace biota::models::plants {

using core::Real;
using core::Vec3;

/// \brief What the contact law reads of a sphere, in one record (two cache lines).
struct SphereHot {
  Vec3 x, v, w;
  Real r, pad[2];
};

/// \brief Contact law coefficients (MechanicsParams: contact_k, contact_c, friction, friction_c).
struct ContactLaw {
  Real k, c, mu, mu_c;
};

/// \brief The law for the pair (a, b), a the lower global id: false when the two do not touch
/// (nothing to add), else the force `f` and torque `t` on the sphere of `side` (0: a, 1: b).
/// The side is applied by selects, not a branch (it is as good as random per pair).
inline bool evaluate_contact(const SphereHot& a, const SphereHot& b, std::uint32_t side,
                             const ContactLaw& law, Vec3& f, Vec3& t) {
  const Vec3 d = a.x - b.x;
  const Real ri = a.r, rj = b.r, d2 = core::dot(d, d);
  // Clearly apart (a margin far above round-off): skip the square root; else the exact test.
  if (d2 > (ri + rj) * (ri + rj) * (1 + 1e-9)) return false;
  const Real dist = std::sqrt(d2);
  const Real overlap = ri + rj - dist;
  if (overlap <= 0 || dist <= 0) return false;
  const Vec3 n = d / dist;
  const Vec3 vrel = (a.v + core::cross(a.w, n * (-ri))) - (b.v + core::cross(b.w, n * rj));
  const Real vn = core::dot(vrel, n);
  const Real fn = std::max(0.0, law.k * overlap - law.c * vn);
  const Vec3 vt = vrel - n * vn;
  const Real vtn = core::norm(vt);
  Vec3 ft{};
  if (vtn > 0) ft = vt * (-std::min(law.mu_c * vtn, law.mu * fn) / vtn);
  const Vec3 F = n * fn + ft;
  const Vec3 t0 = core::cross(n * (-ri), ft), t1 = core::cross(n * rj, -ft);
  const bool second = side != 0;
  f = {second ? -F.x : F.x, second ? -F.y : F.y, second ? -F.z : F.z};
  t = {second ? t1.x : t0.x, second ? t1.y : t0.y, second ? t1.z : t0.z};
  return true;
}

}  // namespace biota::models::plants
