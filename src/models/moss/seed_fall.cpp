#include "models/moss/seed_fall.hpp"

#include <algorithm>
#include <cmath>

#include "models/flock/boid_noise.hpp"

namespace biota::models::moss {

std::vector<Vec3> face_normals(const std::vector<Vec3>& v,
                               const std::vector<std::array<int, 3>>& tris) {
  std::vector<Vec3> n(tris.size());
  for (std::size_t f = 0; f < tris.size(); ++f) {
    const Vec3 c = core::cross(v[tris[f][1]] - v[tris[f][0]], v[tris[f][2]] - v[tris[f][0]]);
    n[f] = c / core::norm(c);
  }
  return n;
}

std::optional<Landing> drop_seed(const PhotonTracer& tracer, const std::vector<Vec3>& normals,
                                 const std::vector<Vec3>& moss_centres,
                                 const std::vector<int>& moss_faces,
                                 const std::vector<int>& moss_layers, int max_layers,
                                 const Vec3& start, double size) {
  const auto hit = tracer.cast(start, {0, -1, 0});
  if (!hit) return std::nullopt;  // fell past the terrain
  Landing l;
  if (hit->geometry == 1) {  // a moss box: only its top face holds a seed
    const std::size_t m = hit->primitive;
    if (!(hit->x.y > moss_centres[m].y)) return std::nullopt;   // from inside the box
    if (moss_layers[m] + 1 >= max_layers) return std::nullopt;  // rolls off the top layer
    l.face = moss_faces[m];
    l.on_moss = true;
    l.layer = moss_layers[m] + 1;
  } else {
    const Vec3& n = normals[hit->primitive];
    if (!(n.y > 0)) return std::nullopt;  // back face (erratum 26)
    l.face = static_cast<int>(hit->primitive);
  }
  l.centre = hit->x + Vec3{0, 0.5 * size, 0};
  return l;
}

SurfaceSampler::SurfaceSampler(const std::vector<Vec3>& v,
                               const std::vector<std::array<int, 3>>& tris,
                               const std::vector<Vec3>& normals)
    : vertices_(&v), triangles_(&tris) {
  double sum = 0;
  for (std::size_t f = 0; f < tris.size(); ++f) {
    if (!(normals[f].y > 0)) continue;
    sum +=
        0.5 * core::norm(core::cross(v[tris[f][1]] - v[tris[f][0]], v[tris[f][2]] - v[tris[f][0]]));
    faces_.push_back(static_cast<int>(f));
    cumulative_.push_back(sum);
  }
}

Landing SurfaceSampler::sample(core::Rng& rng, double size) const {
  const double u = rng.uniform() * area();
  const std::size_t k = std::min<std::size_t>(
      faces_.size() - 1,
      static_cast<std::size_t>(std::upper_bound(cumulative_.begin(), cumulative_.end(), u) -
                               cumulative_.begin()));
  const auto& t = (*triangles_)[faces_[k]];
  const auto& v = *vertices_;
  const double r1 = std::sqrt(rng.uniform()), r2 = rng.uniform();
  const Vec3 p = v[t[0]] * (1 - r1) + v[t[1]] * (r1 * (1 - r2)) + v[t[2]] * (r1 * r2);
  Landing l;
  l.face = faces_[k];
  l.centre = p + Vec3{0, 0.5 * size, 0};
  return l;
}

GrowthNoise::GrowthNoise(double amplitude, double hurst, int levels, std::uint64_t seed,
                         const Vec3& lo, const Vec3& hi)
    : amplitude_(amplitude), n_((1 << levels) + 1), lo_(lo), hi_(hi) {
  if (amplitude_ <= 0) return;
  fx_ = flock::normalized_fbm_field(levels, hurst, seed, 0x6d6f7373);  // "moss"
  fz_ = flock::normalized_fbm_field(levels, hurst, seed, 0x6d6f7374);
}

double GrowthNoise::sample(const std::vector<double>& f, double u, double v) const {
  const double s = std::clamp(u, 0.0, 1.0) * (n_ - 1), t = std::clamp(v, 0.0, 1.0) * (n_ - 1);
  const int i = std::min(n_ - 2, static_cast<int>(s)), j = std::min(n_ - 2, static_cast<int>(t));
  const double a = s - i, b = t - j;
  auto at = [&](int p, int q) { return f[static_cast<std::size_t>(p + n_ * q)]; };
  return (1 - a) * (1 - b) * at(i, j) + a * (1 - b) * at(i + 1, j) + (1 - a) * b * at(i, j + 1) +
         a * b * at(i + 1, j + 1);
}

Vec3 GrowthNoise::offset(const Vec3& p) const {
  if (amplitude_ <= 0) return {0, 0, 0};
  // One square over the footprint (the larger side), so the field is isotropic.
  const double side = std::max(hi_.x - lo_.x, hi_.z - lo_.z);
  const double u = (p.x - lo_.x) / side, v = (p.z - lo_.z) / side;
  return {amplitude_ * sample(fx_, u, v), 0, amplitude_ * sample(fz_, u, v)};
}

bool is_rain_day(long long day, int rain_days) {
  return (day + 1) * rain_days / 365 > day * rain_days / 365;
}

}  // namespace biota::models::moss
