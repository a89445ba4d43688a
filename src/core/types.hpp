#pragma once
/// \file types.hpp
/// \brief Basic value types shared by every layer.
#include <array>
#include <cmath>
#include <cstdint>

namespace biota::core {

/// \brief Floating-point type of all physical state.
using Real = double;
/// \brief Global 64-bit identity of an entity (plant node, boid, moss patch).
using GlobalId = std::uint64_t;

/// \brief Integer index triple (cells, ranks, dimensions).
struct Index3 {
  int x = 0, y = 0, z = 0;
  constexpr int& operator[](int d) { return d == 0 ? x : (d == 1 ? y : z); }
  constexpr int operator[](int d) const { return d == 0 ? x : (d == 1 ? y : z); }
  constexpr bool operator==(const Index3&) const = default;
  constexpr long long product() const { return 1LL * x * y * z; }
};

/// \brief Small 3-vector with the arithmetic the models need.
struct Vec3 {
  Real x = 0, y = 0, z = 0;
  constexpr Real& operator[](int d) { return d == 0 ? x : (d == 1 ? y : z); }
  constexpr Real operator[](int d) const { return d == 0 ? x : (d == 1 ? y : z); }
  constexpr Vec3& operator+=(const Vec3& o) {
    x += o.x;
    y += o.y;
    z += o.z;
    return *this;
  }
  constexpr Vec3& operator-=(const Vec3& o) {
    x -= o.x;
    y -= o.y;
    z -= o.z;
    return *this;
  }
  constexpr Vec3& operator*=(Real s) {
    x *= s;
    y *= s;
    z *= s;
    return *this;
  }
  friend constexpr Vec3 operator+(Vec3 a, const Vec3& b) { return a += b; }
  friend constexpr Vec3 operator-(Vec3 a, const Vec3& b) { return a -= b; }
  friend constexpr Vec3 operator-(const Vec3& a) { return {-a.x, -a.y, -a.z}; }
  friend constexpr Vec3 operator*(Vec3 a, Real s) { return a *= s; }
  friend constexpr Vec3 operator*(Real s, Vec3 a) { return a *= s; }
  friend constexpr Vec3 operator/(Vec3 a, Real s) { return a *= (1 / s); }
  constexpr bool operator==(const Vec3&) const = default;
};

constexpr Real dot(const Vec3& a, const Vec3& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
constexpr Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline Real norm(const Vec3& a) {
  return std::sqrt(dot(a, a));
}

}  // namespace biota::core
