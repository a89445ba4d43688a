#pragma once
/// \file photon_tracer.hpp
/// \brief Photon tracing pass of photon mapping on the terrain and the moss models (spec moss.md
/// 2.5): Embree closest-hit rays; at every hit the photon is stored and then diffusely reflected
/// ((3.1) about the normal) with probability equal to the surface's reflectance, else absorbed.
///
/// Every photon draws from its own core::Rng stream keyed by (seed, photon id, day), so a photon's
/// path and stored hits do not depend on which rank traces it. The scene (terrain and every moss
/// box) is replicated on each rank; it is small (a few 10⁴ triangles).
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "models/moss/light_source.hpp"

namespace biota::models::moss {

/// \brief One stored photon hit.
struct PhotonHit {
  Vec3 x;
  std::uint64_t photon = 0;
  int bounce = 0;
};

/// \brief Result of one ray cast.
struct RayHit {
  double t = 0;
  Vec3 x;
  Vec3 normal;             ///< unit geometric normal as stored (not flipped towards the ray)
  int geometry = 0;        ///< 0 terrain, 1 moss
  unsigned primitive = 0;  ///< triangle of the terrain, or moss index for geometry 1
};

/// \brief Counts of one tracing call.
struct TraceStats {
  long long draws = 0;  ///< conditioned emission draws (see emit_photon)
  long long photons = 0, stored = 0, lost = 0;
};

/// \brief Embree scene and tracer; see file comment.
class PhotonTracer {
 public:
  /// \param reflectance per terrain triangle, in [0, 1].
  PhotonTracer(const std::vector<Vec3>& vertices, const std::vector<std::array<int, 3>>& triangles,
               std::vector<double> reflectance);
  ~PhotonTracer();
  PhotonTracer(const PhotonTracer&) = delete;
  PhotonTracer& operator=(const PhotonTracer&) = delete;

  /// \brief Replace the moss occluders: an axis-aligned cube of edge `size` centred at each
  /// position, reflectance `moss_reflectance`. Rebuilds the scene (once a day).
  void set_mosses(const std::vector<Vec3>& positions, double size, double moss_reflectance);

  /// \brief Closest hit along origin + t dir, t in (0, t_max]; dir need not be unit (t in its
  /// units).
  std::optional<RayHit> cast(const Vec3& origin, const Vec3& dir, double t_max = 1e30) const;

  /// \brief Trace photons [first, last) of `day`; append every stored hit to `out`.
  /// indirect = false stores the first hit only (experiment 1). Paths stop after `max_bounces`
  /// reflections (a safety cap; Russian roulette ends them long before for reflectance < 0.9).
  TraceStats trace(const SquareLight& light, const BoundingSphere& scene, std::uint64_t seed,
                   std::uint64_t day, std::uint64_t first, std::uint64_t last, bool indirect,
                   int max_bounces, std::vector<PhotonHit>& out) const;

  /// \brief Bounding sphere of the terrain (centre of the box, half its diagonal), times `margin`.
  BoundingSphere bounding_sphere(double margin = 1.0) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace biota::models::moss
