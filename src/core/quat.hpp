#pragma once
/// \file quat.hpp
/// \brief Unit quaternions for orientations (rigid spheres, growth frames).
#include <cmath>

#include "core/types.hpp"

namespace biota::core {

/// \brief Quaternion w + xi + yj + zk; unit quaternions represent rotations.
struct Quat {
  Real w = 1, x = 0, y = 0, z = 0;
  friend Quat operator*(const Quat& a, const Quat& b) {
    return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z,
            a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
            a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
            a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
  }
  Quat conj() const { return {w, -x, -y, -z}; }
  Quat normalized() const {
    const Real n = std::sqrt(w * w + x * x + y * y + z * z);
    return {w / n, x / n, y / n, z / n};
  }
  /// \brief Rotate vector v (v' = q v q*).
  Vec3 rotate(const Vec3& v) const {
    const Vec3 u{x, y, z};
    const Vec3 t = 2.0 * cross(u, v);
    return v + w * t + cross(u, t);
  }
  /// \brief Rotation of `angle` (rad) about unit `axis`.
  static Quat axis_angle(const Vec3& axis, Real angle) {
    const Real s = std::sin(0.5 * angle);
    return {std::cos(0.5 * angle), axis.x * s, axis.y * s, axis.z * s};
  }
  /// \brief Rotation vector (axis * angle, angle in [0, pi]) of this unit quaternion.
  Vec3 rotation_vector() const {
    Quat q = w < 0 ? Quat{-w, -x, -y, -z} : *this;
    const Real s = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z);
    if (s < 1e-12) return {2 * q.x, 2 * q.y, 2 * q.z};
    const Real angle = 2 * std::atan2(s, q.w);
    return Vec3{q.x, q.y, q.z} * (angle / s);
  }
  /// \brief Advance by angular velocity omega (world frame) over dt (exact exponential map).
  /// For a half-angle theta = |omega| dt / 2 below 0.01 (every sub-step of the seaweed run) the
  /// rotation's cos(theta) and sin(theta) / |omega| come from their Taylor series, whose first
  /// dropped terms are below 1e-21 relative: the map to round-off, without the square root, the
  /// three divisions and libm's sincos (5% of a seaweed cycle-5 profile). Larger angles: libm.
  Quat integrated(const Vec3& omega, Real dt) const {
    const Real w2 = dot(omega, omega);
    if (w2 * dt * dt < 1e-30) return *this;
    const Real t2 = 0.25 * w2 * dt * dt;  // theta^2
    Real c, s_over_w;
    if (t2 < 1e-4) {
      small_rotation(t2, dt, c, s_over_w);
    } else {
      const Real wn = std::sqrt(w2), half = 0.5 * wn * dt;
      c = std::cos(half);
      s_over_w = std::sin(half) / wn;
    }
    return rotated(c, omega, s_over_w);
  }
  /// \brief integrated()'s cos(theta) and sin(theta) / |omega| for theta^2 = t2 < 1e-4, from
  /// their Taylor series (no branch: vector lanes use it too).
  static void small_rotation(Real t2, Real dt, Real& c, Real& s_over_w) {
    c = 1 + t2 * (-1.0 / 2 + t2 * (1.0 / 24 + t2 * (-1.0 / 720 + t2 * (1.0 / 40320))));
    s_over_w =
        0.5 * dt * (1 + t2 * (-1.0 / 6 + t2 * (1.0 / 120 + t2 * (-1.0 / 5040 + t2 / 362880))));
  }
  /// \brief integrated()'s last step: r * this, normalised, with r = (c, omega s_over_w).
  Quat rotated(Real c, const Vec3& omega, Real s_over_w) const {
    const Quat r{c, omega.x * s_over_w, omega.y * s_over_w, omega.z * s_over_w};
    return (r * (*this)).normalized();
  }
};

}  // namespace biota::core
