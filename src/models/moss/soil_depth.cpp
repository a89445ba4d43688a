#include "models/moss/soil_depth.hpp"

#include <algorithm>

namespace biota::models::moss {

std::vector<double> soil_depth_mm(const PhotonTracer& tracer, const std::vector<Vec3>& v,
                                  const std::vector<std::array<int, 3>>& tris) {
  constexpr double kStart = 1e-4;  // m below the surface, so the ray does not hit its own face
  std::vector<double> h(tris.size(), 1.0);
  for (std::size_t f = 0; f < tris.size(); ++f) {
    const Vec3 a = v[tris[f][0]], b = v[tris[f][1]], c = v[tris[f][2]];
    const Vec3 n = core::cross(b - a, c - a);
    if (n.y < 0.1 * core::norm(n)) continue;  // wall or downward face: h = 1 mm
    const Vec3 o = (a + b + c) / 3.0 - Vec3{0, kStart, 0};
    const auto hit = tracer.cast(o, {0, -1, 0});
    h[f] = hit ? std::clamp(1000.0 * (hit->t + kStart), 1.0, 1000.0) : 1000.0;
  }
  return h;
}

}  // namespace biota::models::moss
