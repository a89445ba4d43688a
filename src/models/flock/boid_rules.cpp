#include "models/flock/boid_rules.hpp"

#include <cmath>
#include <stdexcept>

namespace biota::models::flock {

double polarisation(std::span<const Vec3> velocities) {
  Vec3 sum{};
  std::size_t n = 0;
  for (const Vec3& v : velocities) {
    const Real s = core::norm(v);
    if (s == 0) continue;
    sum += v / s;
    ++n;
  }
  return n == 0 ? 0.0 : core::norm(sum) / double(n);
}

}  // namespace biota::models::flock
