#include "models/moss/light_source.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace biota::models::moss {

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;

Vec3 unit(const Vec3& a) {
  return a / core::norm(a);
}

// Any unit vector perpendicular to n.
Vec3 perpendicular(const Vec3& n) {
  const Vec3 a = std::abs(n.y) < 0.9 ? Vec3{0, 1, 0} : Vec3{1, 0, 0};
  return unit(core::cross(a, n));
}
}  // namespace

Vec3 sun_direction_from_angles(double elevation_deg, double azimuth_deg) {
  const double e = elevation_deg * kDeg, a = azimuth_deg * kDeg;
  return {std::cos(e) * std::sin(a), std::sin(e), -std::cos(e) * std::cos(a)};
}

Vec3 sun_direction_from_date(int day, double hour, double latitude_deg) {
  const double decl = 23.45 * kDeg * std::sin(2 * std::numbers::pi * (284 + day) / 365.0);
  const double h = 15.0 * (hour - 12.0) * kDeg, phi = latitude_deg * kDeg;
  const double sin_e =
      std::sin(phi) * std::sin(decl) + std::cos(phi) * std::cos(decl) * std::cos(h);
  if (sin_e <= 0) throw std::invalid_argument("the sun is below the horizon at that date and hour");
  // East-north-up components of the direction to the sun.
  const double east = -std::cos(decl) * std::sin(h);
  const double north =
      std::cos(phi) * std::sin(decl) - std::sin(phi) * std::cos(decl) * std::cos(h);
  return unit(Vec3{east, sin_e, -north});
}

SquareLight sun_light(const Vec3& to_sun, const BoundingSphere& s, double factor) {
  SquareLight l;
  const Vec3 d = unit(to_sun);
  l.centre = s.centre + d * (factor * s.radius);
  l.normal = -d;
  l.u = perpendicular(l.normal);
  l.v = core::cross(l.normal, l.u);
  l.half = s.radius;
  return l;
}

Vec3 cosine_direction(const Vec3& n, double xi1, double xi2) {
  const double cos_t = std::sqrt(xi1), sin_t = std::sqrt(1.0 - xi1);
  const double phi = 2 * std::numbers::pi * xi2;
  const Vec3 u = perpendicular(n), v = core::cross(n, u);
  return n * cos_t + u * (sin_t * std::cos(phi)) + v * (sin_t * std::sin(phi));
}

double emission_cone_cos2(const SquareLight& l, const BoundingSphere& s) {
  const double dist = core::dot(s.centre - l.centre, l.normal);
  if (dist <= s.radius + std::sqrt(2.0) * l.half) return 0.0;
  const double t = std::atan(std::sqrt(2.0) * l.half / dist) + std::asin(s.radius / dist);
  if (t >= std::numbers::pi / 2) return 0.0;
  return std::cos(t) * std::cos(t);
}

bool emit_photon(const SquareLight& l, const BoundingSphere& s, double cos2_max, core::Rng& rng,
                 long long max_draws, Emission& out) {
  out.draws = 0;
  while (out.draws < max_draws) {
    ++out.draws;
    const double a = rng.uniform(-1, 1), b = rng.uniform(-1, 1);
    const double xi1 = cos2_max + (1.0 - cos2_max) * rng.uniform(), xi2 = rng.uniform();
    out.origin = l.centre + l.u * (a * l.half) + l.v * (b * l.half);
    out.dir = cosine_direction(l.normal, xi1, xi2);
    // Ray-sphere: closest approach of the forward ray to the centre within the radius.
    const Vec3 oc = s.centre - out.origin;
    const double t = core::dot(oc, out.dir);
    const double d2 = core::dot(oc, oc) - t * t;
    const bool inside = core::dot(oc, oc) <= s.radius * s.radius;
    if (inside || (t > 0 && d2 <= s.radius * s.radius)) return true;
  }
  return false;
}

double photon_density_per_draw(const SquareLight& l, const Vec3& p, const Vec3& n) {
  constexpr int kQ = 64;
  double sum = 0;
  for (int i = 0; i < kQ; ++i)
    for (int j = 0; j < kQ; ++j) {
      const double a = -1 + (2 * i + 1.0) / kQ, b = -1 + (2 * j + 1.0) / kQ;
      const Vec3 x = l.centre + l.u * (a * l.half) + l.v * (b * l.half);
      const Vec3 r = p - x;
      const double d2 = core::dot(r, r), d = std::sqrt(d2);
      const double cl = core::dot(l.normal, r) / d, cs = -core::dot(n, r) / d;
      if (cl > 0 && cs > 0) sum += cl * cs / (std::numbers::pi * d2);
    }
  return sum / (kQ * kQ);
}

}  // namespace biota::models::moss
