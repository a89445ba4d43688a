// The flock's initial state: the take-off points (chaos game or uniform), each prey's cruising
// distance and top speed from the fBm fields, the predators' start.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>

#include "core/rng.hpp"
#include "models/flock/chaos_game.hpp"
#include "scenarios/flock_scenario.hpp"

namespace biota::scenarios {

namespace mf = models::flock;
using core::Vec3;

void FlockScenario::place_boids() {
  const auto& c = ctx_.config;
  const std::string ifs = c.get_string("flock.takeoff.ifs");
  const int me = decomp_->rank();
  // Per-boid parameters: d* and v_max from 2D fBm fields over the take-off grid (spec 2.6).
  const double eps_d = c.get_real("flock.noise.cruising_distance");
  const double eps_v = c.get_real("flock.noise.max_speed");
  const double d0 = c.get_real("flock.boids.cruising_distance");
  const double v0 = c.get_real("flock.boids.max_speed");
  int levels = 0;
  while ((1LL << levels) + 1 < static_cast<long long>(std::ceil(std::sqrt(double(n_prey_)))))
    ++levels;
  const long long G = (1LL << levels) + 1;
  std::vector<double> fd, fv;
  if (eps_d > 0) fd = mf::normalized_fbm_field(levels, noise_hurst_, seed_, 1);
  if (eps_v > 0) fv = mf::normalized_fbm_field(levels, noise_hurst_, seed_, 2);
  auto param = [&](const std::vector<double>& f, double base, double eps, long long k) {
    if (f.empty()) return base;
    const long long gi = k % G, gj = k / G;
    return base * std::max(0.1, 1 + eps * f[static_cast<std::size_t>(gi + G * gj)]);
  };

  std::vector<Vec3> pts;
  if (ifs == "uniform") {
    pts.resize(static_cast<std::size_t>(n_prey_));
    for (long long k = 0; k < n_prey_; ++k) {
      core::Rng r(seed_, static_cast<std::uint64_t>(k), 0, core::RngPurpose::kBoidInit);
      pts[k] = {r.uniform(lo_.x, hi_.x), r.uniform(lo_.y, hi_.y), r.uniform(lo_.z, hi_.z)};
    }
    takeoff_interval_ = 0;
  } else {
    std::unique_ptr<mf::ChaosGame> game;
    if (ifs == "gasket") game = std::make_unique<mf::ChaosGame>(mf::ChaosGame::sierpinski_gasket());
    if (ifs == "fern") game = std::make_unique<mf::ChaosGame>(mf::ChaosGame::barnsley_fern());
    if (ifs == "tetrahedron")
      game = std::make_unique<mf::ChaosGame>(mf::ChaosGame::sierpinski_tetrahedron());
    if (ifs == "user") {
      const auto& maps = c.get_real_list("flock.takeoff.maps");
      try {
        game = std::make_unique<mf::ChaosGame>(
            mf::ChaosGame::from_flat(static_cast<int>(c.get_int("flock.takeoff.dim")), maps));
      } catch (const std::invalid_argument& e) {
        c.fail("flock.takeoff.maps", e.what());
      }
    }
    // The orbit is a serial chain: every rank builds the same one (spec 2.7, take-off order =
    // generation order = prey id).
    auto orbit = game->generate(static_cast<std::size_t>(n_prey_), seed_, 0);
    Vec3 mn = orbit[0], mx = orbit[0];
    for (const auto& p : orbit)
      for (int d = 0; d < 3; ++d) mn[d] = std::min(mn[d], p[d]), mx[d] = std::max(mx[d], p[d]);
    double ext = 0;
    for (int d = 0; d < 3; ++d) ext = std::max(ext, mx[d] - mn[d]);
    if (ext == 0) ext = 1;
    const double scale = c.get_real("flock.takeoff.scale") / ext;
    const auto& o = c.get_real_list("flock.takeoff.origin");
    const bool xz = c.get_string("flock.takeoff.plane") == "xz";
    pts.resize(orbit.size());
    for (std::size_t k = 0; k < orbit.size(); ++k) {
      const Vec3 u = (orbit[k] - mn) * scale;
      if (game->dim() == 3)
        pts[k] = {o[0] + u.x, o[1] + u.y, o[2] + u.z};
      else
        pts[k] = xz ? Vec3{o[0] + u.x, o[1], o[2] + u.y} : Vec3{o[0] + u.x, o[1] + u.y, o[2]};
    }
    // The pattern lies in the box, as the origin does: its extent along each box axis per metre
    // of flock.takeoff.scale, from the orbit (u above reaches infinity for a huge scale).
    const Vec3 span = (mx - mn) / ext;
    const Vec3 unit = game->dim() == 3 ? span
                      : xz             ? Vec3{span.x, 0, span.y}
                                       : Vec3{span.x, span.y, 0};
    const auto& box = c.get_real_list("flock.domain.size");
    double fits = std::numeric_limits<double>::infinity();
    for (int d = 0; d < 3; ++d)
      if (unit[d] > 0) fits = std::min(fits, (box[d] - o[d]) / unit[d]);
    if (c.get_real("flock.takeoff.scale") > fits)
      c.fail(
          "flock.takeoff.scale",
          fmt::format("m puts the take-off pattern outside the box [0, {}] x [0, {}] x [0, {}] m "
                      "from flock.takeoff.origin; allowed: at most {:.6g} m from this origin",
                      box[0], box[1], box[2], fits));
  }
  for (long long k = 0; k < n_prey_ + n_pred_; ++k) {
    const bool prey = k < n_prey_;
    const Vec3 p = prey ? pts[k] : pred_start_ + Vec3{2.0 * double(k - n_prey_), 0, 0};
    if (pcomm_->owner_of(p) != me) continue;
    const std::size_t i = set_->add_owned(static_cast<core::GlobalId>(k), p);
    set_->real(a_dstar_)[i] = prey ? param(fd, d0, eps_d, k) : d0;
    set_->real(a_vmax_)[i] = prey ? param(fv, v0, eps_v, k) : pred_vmax_;
    if (prey && ifs == "uniform") {  // all flying at t = 0 with random headings
      core::Rng r(seed_, static_cast<std::uint64_t>(k), 1, core::RngPurpose::kBoidInit);
      const double z = r.uniform(-1, 1), phi = r.uniform(0, 2 * std::numbers::pi);
      const double sn = std::sqrt(1 - z * z), sp = 0.5 * (v_min_ + set_->real(a_vmax_)[i]);
      set_->set_vec3(a_vel_, i, Vec3{sn * std::cos(phi), sn * std::sin(phi), z} * sp);
    }
  }
}

}  // namespace biota::scenarios
