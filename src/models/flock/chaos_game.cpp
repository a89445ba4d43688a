/// \file chaos_game.cpp
/// \brief Chaos-game iteration and IFS presets.
#include "models/flock/chaos_game.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "core/rng.hpp"

namespace biota::models::flock {

ChaosGame::ChaosGame(int dim, std::vector<AffineMap> maps) : dim_(dim), maps_(std::move(maps)) {
  if (dim != 2 && dim != 3) throw std::invalid_argument("ChaosGame: dim must be 2 or 3");
  if (maps_.empty()) throw std::invalid_argument("ChaosGame: no maps");
  double total = 0;
  for (const auto& m : maps_) {
    if (!(m.p >= 0)) throw std::invalid_argument("ChaosGame: negative or NaN probability");
    total += m.p;
  }
  if (std::abs(total - 1.0) > 1e-9)
    throw std::invalid_argument("ChaosGame: probabilities sum to " + std::to_string(total) +
                                ", not 1");
  double c = 0;
  for (auto& m : maps_) {
    m.p /= total;
    if (dim_ == 2) {  // a 2D map must not leak into z
      m.a[2] = m.a[5] = m.a[6] = m.a[7] = m.a[8] = 0;
      m.t.z = 0;
    }
    c += m.p;
    cumulative_.push_back(c);
  }
  cumulative_.back() = 1.0;
}

ChaosGame ChaosGame::from_flat(int dim, std::span<const double> v) {
  const std::size_t per = dim == 2 ? 7 : 13;
  if ((dim != 2 && dim != 3) || v.empty() || v.size() % per != 0)
    throw std::invalid_argument(
        "ChaosGame::from_flat: need dim 2 with 7 or dim 3 with 13 reals "
        "per map, got " +
        std::to_string(v.size()) + " reals");
  std::vector<AffineMap> maps;
  for (std::size_t k = 0; k < v.size(); k += per) {
    AffineMap m;
    if (dim == 2) {
      m.a = {v[k], v[k + 1], 0, v[k + 2], v[k + 3], 0, 0, 0, 0};
      m.t = {v[k + 4], v[k + 5], 0};
      m.p = v[k + 6];
    } else {
      std::copy(v.begin() + k, v.begin() + k + 9, m.a.begin());
      m.t = {v[k + 9], v[k + 10], v[k + 11]};
      m.p = v[k + 12];
    }
    maps.push_back(m);
  }
  return ChaosGame(dim, std::move(maps));
}

ChaosGame ChaosGame::sierpinski_gasket() {
  const double t = 1.0 / 3.0;
  const double v[] = {0.5, 0, 0, 0.5, 0,    0,   t,  //
                      0.5, 0, 0, 0.5, 0.5,  0,   t,  //
                      0.5, 0, 0, 0.5, 0.25, 0.5, t};
  return from_flat(2, v);
}

ChaosGame ChaosGame::barnsley_fern() {
  const double v[] = {0,     0,     0,     0.16, 0, 0,    0.01,  //
                      0.85,  0.04,  -0.04, 0.85, 0, 1.6,  0.85,  //
                      0.20,  -0.26, 0.23,  0.22, 0, 1.6,  0.07,  //
                      -0.15, 0.28,  0.26,  0.24, 0, 0.44, 0.07};
  return from_flat(2, v);
}

ChaosGame ChaosGame::sierpinski_tetrahedron() {
  const core::Vec3 verts[4] = {{0, 0, 0},
                               {1, 0, 0},
                               {0.5, std::sqrt(3.0) / 2, 0},
                               {0.5, std::sqrt(3.0) / 6, std::sqrt(2.0 / 3.0)}};
  std::vector<AffineMap> maps;
  for (const auto& vx : verts) {
    AffineMap m;
    m.a = {0.5, 0, 0, 0, 0.5, 0, 0, 0, 0.5};
    m.t = vx * 0.5;
    m.p = 0.25;
    maps.push_back(m);
  }
  return ChaosGame(3, std::move(maps));
}

core::Vec3 ChaosGame::start_point() const {
  // Solve (I - A) x = T by Cramer's rule on the active dim × dim block.
  const auto& m = maps_.front();
  double b[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) b[i][j] = (i == j ? 1.0 : 0.0) - m.a[3 * i + j];
  if (dim_ == 2) {
    const double det = b[0][0] * b[1][1] - b[0][1] * b[1][0];
    if (std::abs(det) < 1e-12) return {};
    return {(m.t.x * b[1][1] - b[0][1] * m.t.y) / det, (b[0][0] * m.t.y - b[1][0] * m.t.x) / det,
            0};
  }
  auto det3 = [](const double c[3][3]) {
    return c[0][0] * (c[1][1] * c[2][2] - c[1][2] * c[2][1]) -
           c[0][1] * (c[1][0] * c[2][2] - c[1][2] * c[2][0]) +
           c[0][2] * (c[1][0] * c[2][1] - c[1][1] * c[2][0]);
  };
  const double det = det3(b);
  if (std::abs(det) < 1e-12) return {};
  core::Vec3 x;
  for (int col = 0; col < 3; ++col) {
    double c[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) c[i][j] = j == col ? m.t[i] : b[i][j];
    x[col] = det3(c) / det;
  }
  return x;
}

std::vector<core::Vec3> ChaosGame::generate(std::size_t n, std::uint64_t seed,
                                            std::uint64_t stream_id, int transient) const {
  core::Rng rng(seed, stream_id, 0, core::RngPurpose::kChaosGame);
  auto step = [&](const core::Vec3& x) {
    const double u = rng.uniform();
    const auto it = std::upper_bound(cumulative_.begin(), cumulative_.end(), u);
    const std::size_t k = std::min<std::size_t>(it - cumulative_.begin(), maps_.size() - 1);
    return maps_[k].apply(x);
  };
  core::Vec3 x = start_point();
  for (int i = 0; i < transient; ++i) x = step(x);
  std::vector<core::Vec3> out;
  out.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    x = step(x);
    out.push_back(x);
  }
  return out;
}

}  // namespace biota::models::flock
