#pragma once
/// \file light_source.hpp
/// \brief The sun of the moss model (spec moss.md 2.5, errata 4 and 5): a square planar source on
/// the sun's direction, cosine-weighted emission (3.1), emission culling against the scene's
/// bounding sphere, and the per-draw photon density used to calibrate the photon power.
///
/// Frame: +y up, north = -z, east = +x. Azimuth is measured from north towards east.
#include "core/rng.hpp"
#include "core/types.hpp"

namespace biota::models::moss {

using core::Vec3;

struct BoundingSphere {
  Vec3 centre;
  double radius = 0;
};

/// \brief Square of side 2 `half` centred at `centre`, emitting into the half space along `normal`
/// (unit); u, v are unit edge directions.
struct SquareLight {
  Vec3 centre, normal, u, v;
  double half = 0;
  double area() const { return 4 * half * half; }
};

/// \brief Unit vector towards the sun from elevation and azimuth in degrees.
Vec3 sun_direction_from_angles(double elevation_deg, double azimuth_deg);
/// \brief Unit vector towards the sun on day `day_of_year` (1..365) at solar hour `hour` (12 =
/// noon) and latitude (deg, north positive): Cooper's declination 23.45° sin(360° (284 + n) / 365)
/// and hour angle 15° (hour - 12). Throws std::invalid_argument if the sun is below the horizon.
Vec3 sun_direction_from_date(int day_of_year, double hour, double latitude_deg);

/// \brief The sun as a square of side 2 R (R = bounding radius), facing the sphere's centre from
/// `distance_factor` R along `to_sun` (erratum 4: size and distance are ours).
SquareLight sun_light(const Vec3& to_sun, const BoundingSphere& scene, double distance_factor);

/// (3.1): direction about the unit normal n with polar angle acos(sqrt(xi1)), azimuth 2 pi xi2.
Vec3 cosine_direction(const Vec3& n, double xi1, double xi2);

/// \brief One emitted photon: start point, direction, and how many draws it took.
struct Emission {
  Vec3 origin, dir;
  long long draws = 0;
};

/// \brief cos² of the widest polar angle (about the light's normal) at which a ray from any point
/// of the light can meet the sphere: θ_max = atan(√2 half / D) + asin(R / D), D the distance of the
/// sphere's centre from the light's plane; 0 (all directions) if the light is within reach.
double emission_cone_cos2(const SquareLight& light, const BoundingSphere& scene);

/// \brief Emission with culling (2.5): a uniform point on the light and a (3.1) direction, both
/// redrawn until the ray meets the bounding sphere (erratum 5: the point is redrawn too, and every
/// draw counts as emitted, so the photon power stays unbiased). Speed-up, same distribution: ξ1 is
/// drawn in [cos2_max, 1] instead of [0, 1], i.e. the (3.1) direction conditioned on θ < θ_max,
/// which every accepted direction satisfies; one such draw stands for 1 / (1 - cos2_max) draws of
/// the plain method, which the photon power accounts for (PhotonMap). `draws` counts the
/// conditioned draws. Returns false after `max_draws`.
bool emit_photon(const SquareLight& light, const BoundingSphere& scene, double cos2_max,
                 core::Rng& rng, long long max_draws, Emission& out);

/// \brief Expected photons per m² per draw arriving unoccluded at `point` on a surface with unit
/// normal `normal`: (1/A) ∫ cosθ_light cosθ_surface / (π d²) dA over the light (64² midpoint
/// quadrature). The calibration: photon power Φ = S_open / (draws · density at the scene centre on
/// a horizontal surface), so an open horizontal surface receives S_open.
double photon_density_per_draw(const SquareLight& light, const Vec3& point, const Vec3& normal);

}  // namespace biota::models::moss
