#pragma once
/// \file seaweed_contact.hpp
/// \brief The seaweed sphere-sphere contact law (normal spring-damper, Coulomb-capped viscous
/// friction; see SeaweedBodies), split into the evaluation of a pair and the contribution to each
/// of its two spheres, so a pair of two owned spheres can be evaluated once and its second
/// sphere's share added later in that sphere's own summation order (same bits as evaluating it
/// again: the inputs do not change within a sub-step).
#include <algorithm>
#include <cstdint>

#include "core/types.hpp"

namespace biota::models::plants {

using core::Real;
using core::Vec3;

/// What the contact law reads of a sphere, in one record (two cache lines per partner instead of
/// ten columns; partners are read in no particular order).
struct ContactSphere {
  Vec3 x, v, w;
  Real r, pad[2];
};

struct ContactLaw {
  Real k, c, friction, friction_c;  ///< normal stiffness, normal damping, mu, tangential damping
};

/// A touching pair's normal n (first minus second), total force F on the first sphere and its
/// friction part ft.
struct ContactHit {
  Vec3 F, n, ft;
};

/// \brief Evaluate the pair (a, b) in the orientation (lower id, higher id); false when the
/// spheres do not overlap (then neither sphere gets anything).
inline bool contact_hit(const ContactSphere& a, const ContactSphere& b, const ContactLaw& law,
                        ContactHit& h) {
  const Vec3 d = a.x - b.x;
  const Real ra = a.r, rb = b.r, d2 = core::dot(d, d);
  // Clearly apart (a margin far above round-off): skip the square root; else the exact test.
  if (d2 > (ra + rb) * (ra + rb) * (1 + 1e-9)) return false;
  const Real dist = core::norm(d);
  const Real overlap = ra + rb - dist;
  if (overlap <= 0 || dist <= 0) return false;
  const Vec3 n = d / dist;
  const Vec3 vrel = (a.v + core::cross(a.w, n * (-ra))) - (b.v + core::cross(b.w, n * rb));
  const Real vn = core::dot(vrel, n);
  const Real fn = std::max(0.0, law.k * overlap - law.c * vn);
  const Vec3 vt = vrel - n * vn;
  const Real vtn = core::norm(vt);
  Vec3 ft{};
  if (vtn > 0) ft = vt * (-std::min(law.friction_c * vtn, law.friction * fn) / vtn);
  h = {n * fn + ft, n, ft};
  return true;
}

/// \brief Force and torque of a touching pair on its first (side 0, radius ra) or second (side 1,
/// radius rb) sphere.
inline void contact_share(const ContactHit& h, std::uint32_t side, Real ra, Real rb, Vec3& f,
                          Vec3& t) {
  if (side == 0) {
    f = h.F;
    t = core::cross(h.n * (-ra), h.ft);
  } else {
    f = -h.F;
    t = core::cross(h.n * rb, -h.ft);
  }
}

}  // namespace biota::models::plants
