#pragma once
/// \file photon_map.hpp
/// \brief The distributed photon map and insolation S (spec moss.md 2.5 and erratum 2).
///
/// Photons are traced on all ranks: rank r traces the photon ids of its contiguous block of
/// [0, N). The stored hits become a particles::ParticleSet (id = photon id * 128 + bounce), sent
/// to the rank owning their position (redistribute) and copied as ghosts within the search radius
/// r. Each rank builds a nanoflann kd-tree over its owned + ghost hits and counts, for the query
/// points it owns, the hits within r; the counts are integers and summed into one global array, so
/// S = Φ n / (π r²) is the same on any rank count to the last bit. Φ = S_open / (D ρ_ref): D all
/// emission draws (summed exactly as integers, scaled by 1 / (1 - cos2_max), see emit_photon) and
/// ρ_ref the per-draw density of photon_density_ per_draw at the reference point
/// (PhotonMapSettings) on a horizontal surface.
#include <mpi.h>

#include <memory>
#include <optional>
#include <vector>

#include "grid/decomposition.hpp"
#include "models/moss/photon_tracer.hpp"
#include "particles/particle_comm.hpp"

namespace biota::models::moss {

/// \brief Settings of one day's photon map.
struct PhotonMapSettings {
  long long photons = 8192;
  double radius = 0.1;           ///< m, photon count radius r
  double open_insolation = 100;  ///< W/m², S_open: what an open horizontal surface receives
  bool indirect = true;
  int max_bounces = 100;
  double distance_factor = 20;  ///< light at this many bounding radii from the scene centre
  /// Where an open horizontal surface receives exactly S_open (the calibration point); empty: the
  /// bounding sphere's centre. A finite-distance sun gives other points a 1/d² share: ±2 Δy / D.
  std::optional<Vec3> reference;
};

/// \brief Counts of one photon map (global, identical on every rank).
struct PhotonMapStats {
  long long draws = 0;  ///< conditioned emission draws
  long long photons = 0, stored = 0;
  double photon_power = 0;   ///< Φ, W per photon
  double trace_seconds = 0;  ///< this rank: tracing its photons
  double map_seconds = 0;    ///< this rank: redistribution, ghosts, kd-tree build and queries
};

/// \brief Domain of the photon map's rank decomposition; see file comment.
class PhotonMap {
 public:
  /// \param lo, hi box holding every query point and hit (the scene's box); cells of the rank
  /// decomposition are at least `radius`.
  PhotonMap(MPI_Comm comm, const Vec3& lo, const Vec3& hi, double radius);
  ~PhotonMap();

  /// \brief Trace one day's photons and return S (W/m²) at every query point (same array on every
  /// rank). Collective; `queries` must be the same on every rank.
  std::vector<double> insolation(const PhotonTracer& tracer, const SquareLight& light,
                                 const BoundingSphere& sphere, std::uint64_t seed,
                                 std::uint64_t day, const PhotonMapSettings& s,
                                 const std::vector<Vec3>& queries, PhotonMapStats* stats = nullptr);
  /// \brief Photon counts within r of the last call, per query point.
  const std::vector<long long>& counts() const { return counts_; }
  /// \brief Hits owned by this rank after the last call (owned part of the photon map).
  const particles::ParticleSet& hits() const { return *set_; }

 private:
  MPI_Comm comm_;
  double radius_;
  std::unique_ptr<grid::Decomposition> decomp_;
  std::unique_ptr<particles::ParticleComm> pcomm_;
  std::unique_ptr<particles::ParticleSet> set_;
  std::vector<long long> counts_;
};

}  // namespace biota::models::moss
