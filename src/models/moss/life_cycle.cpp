#include "models/moss/life_cycle.hpp"

#include <cmath>
#include <numbers>

namespace biota::models::moss {

MossDay moss_day(const Species& sp, double g, bool spore_day, MossState& st) {
  MossDay d;
  d.growth = daily_growth(sp, g);
  st.g_moss += d.growth;
  ++st.age_days;
  d.dies = st.g_moss < sp.tau_d && d.growth < 0;
  if (d.dies) return d;
  if (st.g_moss > st.g_max) {
    d.gemmae = static_cast<int>(std::floor(st.g_moss / 0.5) - std::floor(st.g_max / 0.5));
    st.g_max = st.g_moss;
  }
  d.spore = spore_day && st.g_moss >= 2.0 && d.growth > 0;
  return d;
}

namespace {
core::Vec3 about(const core::Vec3& n, double cos_t, double phi) {
  const core::Vec3 a = std::abs(n.y) < 0.9 ? core::Vec3{0, 1, 0} : core::Vec3{1, 0, 0};
  core::Vec3 u = core::cross(a, n);
  u = u / core::norm(u);
  const core::Vec3 v = core::cross(n, u);
  const double sin_t = std::sqrt(std::max(0.0, 1 - cos_t * cos_t));
  return n * cos_t + u * (sin_t * std::cos(phi)) + v * (sin_t * std::sin(phi));
}
}  // namespace

core::Vec3 gemma_direction(core::Rng& rng) {
  return about({0, 1, 0}, rng.uniform(-1, 1), 2 * std::numbers::pi * rng.uniform());
}

core::Vec3 spore_direction(const core::Vec3& n, core::Rng& rng) {
  // Uniform in solid angle: cos φ uniform in (cos 45°, 1] on one cone, mirrored for the other.
  const double c = std::sqrt(0.5) + (1 - std::sqrt(0.5)) * rng.uniform();
  const double sign = rng.uniform() < 0.5 ? 1.0 : -1.0;
  return about(n, sign * c, 2 * std::numbers::pi * rng.uniform());
}

}  // namespace biota::models::moss
