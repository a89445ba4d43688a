#pragma once
/// \file seed_fall.hpp
/// \brief Where gemmae, spores and new mosses come to rest (spec moss.md 2.4, 2.7, errata 25, 26):
/// a seed falls along -y from its start point through the photon tracer's scene (terrain and the
/// 1 cm moss boxes); the back-face rule; moss on moss; random drops for the initial placement and
/// the spores from outside; the 1/f (fBm) displacement of growth positions; the rain schedule.
/// Pure (no MPI): every function depends only on its arguments.
#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/rng.hpp"
#include "models/moss/photon_tracer.hpp"

namespace biota::models::moss {

/// \brief A seed at rest: the centre of its 1 cm model (half a model size above the surface
/// point it landed on), the terrain triangle whose soil it uses, and whether it rests on a moss.
struct Landing {
  Vec3 centre;
  int face = -1;
  bool on_moss = false;
  int layer = 0;  ///< 0 on the soil, k + 1 on a moss of layer k
};

/// \brief Outward unit normal (right-hand rule, counter-clockwise vertices as in OBJ) per
/// triangle. Used for the back-face rule and the spore cones; Embree's stored normal is not used
/// because its orientation convention differs.
std::vector<Vec3> face_normals(const std::vector<Vec3>& vertices,
                               const std::vector<std::array<int, 3>>& triangles);

/// \brief Let a seed fall along -y from `start`. Lands on the first surface below it if that is
/// the front of a terrain face (n_y > 0) or the top of a moss box; disappears (nullopt) if it hits
/// nothing, a back face (n . (0, -1, 0) >= 0: undersides, and vertical faces it would slide off),
/// or a moss box from inside. `moss_faces[i]` is the terrain face of moss i of the tracer's moss
/// list (a moss on moss uses the soil of the moss below it), `moss_centres[i]` its centre and
/// `moss_layers[i]` its layer. A seed landing on a moss of layer max_layers - 1 rolls off and is
/// lost (a moss carpet is at most max_layers models thick; without this, towers grew).
std::optional<Landing> drop_seed(const PhotonTracer& tracer, const std::vector<Vec3>& normals,
                                 const std::vector<Vec3>& moss_centres,
                                 const std::vector<int>& moss_faces,
                                 const std::vector<int>& moss_layers, int max_layers,
                                 const Vec3& start, double size);

/// \brief Random points on the upward faces (n_y > 0) of the terrain, uniform by area: the
/// initial placement and the spores from outside (spec 2.4: "random positions on the polygon
/// faces"; faces that look sideways or down cannot hold a seed, erratum 26). Includes the floor
/// under the roof and the roof's top.
class SurfaceSampler {
 public:
  SurfaceSampler(const std::vector<Vec3>& vertices,
                 const std::vector<std::array<int, 3>>& triangles,
                 const std::vector<Vec3>& normals);
  /// \brief A point on a face and the face; the centre of a model there is half a size above.
  Landing sample(core::Rng& rng, double size) const;
  double area() const { return cumulative_.empty() ? 0.0 : cumulative_.back(); }

 private:
  const std::vector<Vec3>* vertices_;
  const std::vector<std::array<int, 3>>* triangles_;
  std::vector<int> faces_;
  std::vector<double> cumulative_;
};

/// \brief 1/f noise on growth positions (spec 2.9): two normalised 2D fBm fields (the flock's
/// midpoint displacement, models/flock) over the scene's x-z footprint give a horizontal offset
/// `amplitude` (F_x(x, z), 0, F_z(x, z)) (bilinear), spatially correlated with a 1/f-type
/// spectrum. Identical on every rank (fields keyed by the seed only).
class GrowthNoise {
 public:
  GrowthNoise() = default;
  GrowthNoise(double amplitude, double hurst, int levels, std::uint64_t seed, const Vec3& lo,
              const Vec3& hi);
  Vec3 offset(const Vec3& p) const;

 private:
  double sample(const std::vector<double>& f, double u, double v) const;
  double amplitude_ = 0;
  int n_ = 0;  // grid points per side
  Vec3 lo_{}, hi_{};
  std::vector<double> fx_, fz_;
};

/// \brief Erratum 11, deterministic reading: rain falls on `rain_days` of every 365, evenly
/// spaced: day d (0-based) is a rain day iff floor((d + 1) r / 365) > floor(d r / 365).
bool is_rain_day(long long day, int rain_days);

}  // namespace biota::models::moss
