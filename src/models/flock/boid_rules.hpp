#pragma once
/// \file boid_rules.hpp
/// \brief Reynolds boid rules as pure kernels (spec boids.md 2.1 and 2.2; Reynolds 1987).
///
/// The paper gives no equations (spec ambiguity 14); the formulas are the standard ones of spec
/// 2.1 [literature]. A boid's acceleration is built in three stages, each a pure function:
///  1. accumulate_neighbour() over the perceived neighbours (perception radius and field of view),
///     in a caller-fixed order (the scenario visits them sorted by global id within globally
///     aligned bins, which makes floating-point sums decomposition-invariant);
///  2. the rule accelerations (separation, alignment, cohesion, flee, chase, soft walls);
///  3. prioritized_sum() — Reynolds' prioritised acceleration allocation — then integrate().
#if defined(__AVX512F__) || defined(__AVX2__)
#include <immintrin.h>
#endif

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>

#include "core/compact_near.hpp"
#include "core/types.hpp"

namespace biota::models::flock {

using core::Real;
using core::Vec3;

/// \brief How alignment (velocity matching, spec 2.1 rule 2) picks its target.
enum class AlignmentMode {
  kNearest,  ///< match the nearest perceived boid (the paper's wording)
  kAverage,  ///< match the mean velocity of the perceived boids (Reynolds 1987)
};

/// \brief Per-boid sums over perceived neighbours (stage 1).
struct NeighbourSums {
  Vec3 separation{};  ///< Σ (x_b - x_j)(d* - r)/r over neighbours closer than d*
  Vec3 velocity{};    ///< Σ v_j
  Vec3 position{};    ///< Σ (x_j - x_b) (relative, so that sums stay well-conditioned)
  int count = 0;      ///< number of perceived neighbours
  Real nearest_r2 = std::numeric_limits<Real>::infinity();  ///< squared distance of the nearest
  std::uint64_t nearest_id = ~std::uint64_t{0};             ///< its global id (tie-break)
  Vec3 nearest_velocity{};                                  ///< its velocity
};

/// \brief True if a boid moving with velocity `v` perceives a point at offset `d` (= x_j - x_b,
/// |d|² = r2): inside the perception radius (r2 < radius2) and inside the field of view, a cone of
/// half-angle acos(fov_cos) about v. fov_cos <= -1 means all around; a boid at rest sees all
/// around (it has no heading).
inline bool perceives(const Vec3& v, const Vec3& d, Real r2, Real radius2, Real fov_cos) {
  if (r2 >= radius2 || r2 <= 0) return false;
  if (fov_cos <= -1) return true;
  const Real vd = core::dot(v, d), v2 = core::dot(v, v);
  if (v2 == 0) return true;
  // vd >= fov_cos |v||d| without square roots where the sign decides.
  if (fov_cos >= 0) return vd >= 0 && vd * vd >= fov_cos * fov_cos * v2 * r2;
  return vd >= 0 || vd * vd <= fov_cos * fov_cos * v2 * r2;
}

/// \brief Add one perceived neighbour j (offset d = x_j - x_b, r2 = |d|², velocity vj, id) to the
/// sums of boid b whose optimal cruising distance is `d_star`. Separation follows spec 2.1:
/// (x_b - x_j)(d* - r)/r for r < d*, a push that grows linearly as the pair closes in below d*.
/// The nearest neighbour is chosen by (distance, id), so ties are broken identically everywhere.
inline void accumulate_neighbour(NeighbourSums& s, const Vec3& d, Real r2, const Vec3& vj,
                                 std::uint64_t id, Real d_star) {
  if (r2 < d_star * d_star) {  // the square root only for the few pairs closer than d*
    const Real r = std::sqrt(r2);
    s.separation -= d * ((d_star - r) / r);
  }
  s.velocity += vj;
  s.position += d;
  ++s.count;
  if (r2 < s.nearest_r2 || (r2 == s.nearest_r2 && id < s.nearest_id)) {
    s.nearest_r2 = r2;
    s.nearest_id = id;
    s.nearest_velocity = vj;
  }
}

#if defined(__AVX512F__)
/// \brief The field-of-view test of perceives() on 8 lanes: v.d >= 0 and (v.d)^2 >= c2 v2 r2
/// (narrow, fov_cos >= 0), else v.d >= 0 or (v.d)^2 <= c2 v2 r2; cv = c2 v2. Separate multiplies
/// and adds, as in the scalar test.
[[gnu::always_inline]] inline __mmask8 in_view8(__m512d vx, __m512d vy, __m512d vz, __m512d dx,
                                                __m512d dy, __m512d dz, __m512d cv, __m512d r2,
                                                bool narrow) {
  const __m512d vd = _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(vx, dx), _mm512_mul_pd(vy, dy)),
                                   _mm512_mul_pd(vz, dz));
  const __m512d vd2 = _mm512_mul_pd(vd, vd), lim = _mm512_mul_pd(cv, r2);
  const __mmask8 ahead = _mm512_cmp_pd_mask(vd, _mm512_setzero_pd(), _CMP_GE_OQ);
  return narrow ? __mmask8(ahead & _mm512_cmp_pd_mask(vd2, lim, _CMP_GE_OQ))
                : __mmask8(ahead | _mm512_cmp_pd_mask(vd2, lim, _CMP_LE_OQ));
}
#endif

#if defined(__AVX2__)
/// \brief in_view8() on 4 lanes, as an all-ones/all-zeros lane mask.
[[gnu::always_inline]] inline __m256d in_view4(__m256d vx, __m256d vy, __m256d vz, __m256d dx,
                                               __m256d dy, __m256d dz, __m256d cv, __m256d r2,
                                               bool narrow) {
  const __m256d vd = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(vx, dx), _mm256_mul_pd(vy, dy)),
                                   _mm256_mul_pd(vz, dz));
  const __m256d vd2 = _mm256_mul_pd(vd, vd), lim = _mm256_mul_pd(cv, r2);
  const __m256d ahead = _mm256_cmp_pd(vd, _mm256_setzero_pd(), _CMP_GE_OQ);
  return narrow ? _mm256_and_pd(ahead, _mm256_cmp_pd(vd2, lim, _CMP_GE_OQ))
                : _mm256_or_pd(ahead, _mm256_cmp_pd(vd2, lim, _CMP_LE_OQ));
}

#endif

/// \brief perceive_compact_r2() with the field-of-view case fixed at compile time (no per-vector
/// test of it in the loop): all round (fov_cos <= -1 or v2 == 0), or narrow (fov_cos >= 0).
namespace detail {
/// The lane test of perceives() beyond the radius: not the boid itself (r2 > 0), and in view.
template <bool kAllRound, bool kNarrow>
struct InView {
  Vec3 v;
  Real cv;  // c2 v2
#if BIOTA_COMPACT_NEAR_LANES == 8
  __mmask8 operator()(__m512d dx, __m512d dy, __m512d dz, __m512d r2) const {
    const __mmask8 apart = _mm512_cmp_pd_mask(r2, _mm512_setzero_pd(), _CMP_GT_OQ);
    if constexpr (kAllRound) return apart;
    return apart & in_view8(_mm512_set1_pd(v.x), _mm512_set1_pd(v.y), _mm512_set1_pd(v.z), dx, dy,
                            dz, _mm512_set1_pd(cv), r2, kNarrow);
  }
#elif BIOTA_COMPACT_NEAR_LANES == 4
  __m256d operator()(__m256d dx, __m256d dy, __m256d dz, __m256d r2) const {
    const __m256d apart = _mm256_cmp_pd(r2, _mm256_setzero_pd(), _CMP_GT_OQ);
    if constexpr (kAllRound) return apart;
    return _mm256_and_pd(
        apart, in_view4(_mm256_set1_pd(v.x), _mm256_set1_pd(v.y), _mm256_set1_pd(v.z), dx, dy, dz,
                        _mm256_set1_pd(cv), r2, kNarrow));
  }
#endif
  bool operator()(Real dx, Real dy, Real dz, Real r2) const {
    const Real vd = v.x * dx + v.y * dy + v.z * dz, lim = cv * r2;
    const bool cone = kNarrow ? (vd >= 0) & (vd * vd >= lim) : (vd >= 0) | (vd * vd <= lim);
    return (r2 > 0) & (kAllRound | cone);
  }
};

template <bool kAllRound, bool kNarrow>
inline std::size_t perceive_compact_r2_fixed(const Real* X, const Real* Y, const Real* Z,
                                             std::size_t n, const Vec3& x, const Vec3& v, Real v2,
                                             Real radius2, Real c2, std::uint64_t* out,
                                             Real* out_r2) {
  return core::compact_near(X, Y, Z, n, x, radius2, std::uint64_t{0}, out, out_r2,
                            InView<kAllRound, kNarrow>{v, c2 * v2});
}
}  // namespace detail

/// \brief The perception test (perceives()) over candidates that are all eligible (the caller
/// filtered them), compacted: writes k and r2_k = |X_k - x|² for every perceived candidate k
/// to `out` and `out_r2` in increasing k and returns their number. Both need room for n + 8
/// entries. r2 is computed as core::dot(d, d) computes it, so sums that reuse it keep their bits.
/// Every candidate, the tail included, goes through the same vector code (AVX-512: 8 lanes, AVX2:
/// 4 lanes, else a branch-free scalar loop), separate multiplies and adds (no FMA), so a decision
/// never depends on a candidate's position in the array.
inline std::size_t perceive_compact_r2(const Real* X, const Real* Y, const Real* Z, std::size_t n,
                                       const Vec3& x, const Vec3& v, Real v2, Real radius2,
                                       Real fov_cos, Real c2, std::uint64_t* out, Real* out_r2) {
  if ((fov_cos <= -1) | (v2 == 0))
    return detail::perceive_compact_r2_fixed<true, false>(X, Y, Z, n, x, v, v2, radius2, c2, out,
                                                          out_r2);
  if (fov_cos >= 0)
    return detail::perceive_compact_r2_fixed<false, true>(X, Y, Z, n, x, v, v2, radius2, c2, out,
                                                          out_r2);
  return detail::perceive_compact_r2_fixed<false, false>(X, Y, Z, n, x, v, v2, radius2, c2, out,
                                                         out_r2);
}

/// \brief Separation acceleration w_sep Σ (x_b - x_j)(d* - r)/r (spec 2.1; units of w: 1/s²).
inline Vec3 separation(const NeighbourSums& s, Real weight) {
  return s.separation * weight;
}

/// \brief Alignment acceleration w_ali (v_target - v_b) (spec 2.1 rule 2; units of w: 1/s).
inline Vec3 alignment(const NeighbourSums& s, const Vec3& v, Real weight, AlignmentMode mode) {
  if (s.count == 0) return {};
  const Vec3 target =
      mode == AlignmentMode::kNearest ? s.nearest_velocity : s.velocity / Real(s.count);
  return (target - v) * weight;
}

/// \brief Cohesion acceleration w_coh (x̄_N - x_b) towards the local centre (spec 2.1 rule 3).
inline Vec3 cohesion(const NeighbourSums& s, Real weight) {
  if (s.count == 0) return {};
  return s.position * (weight / Real(s.count));
}

/// \brief Prey flee (spec 2.2): acceleration of magnitude `weight` (m/s²) straight away from the
/// predator at offset d = x_pred - x_b, if it is closer than `radius` (radius = ∞: always).
/// Zero at zero distance (no direction).
inline Vec3 flee(const Vec3& d, Real radius, Real weight) {
  const Real r2 = core::dot(d, d);
  if (r2 >= radius * radius || r2 == 0) return {};
  return d * (-weight / std::sqrt(r2));
}

/// \brief Predator chase (spec 2.2, erratum 12): acceleration of magnitude `weight` towards the
/// prey at offset d = x_prey - x_pred.
inline Vec3 chase(const Vec3& d, Real weight) {
  const Real r2 = core::dot(d, d);
  if (r2 == 0) return {};
  return d * (weight / std::sqrt(r2));
}

/// \brief Soft walls: inside a layer of thickness `margin` next to a wall of the box [lo, hi],
/// push inwards with weight·(depth/margin)² m/s² (zero at the layer's inner edge, smooth).
/// Outside the box the push is capped at `weight`.
inline Vec3 soft_wall(const Vec3& x, const Vec3& lo, const Vec3& hi, Real margin, Real weight) {
  Vec3 a{};
  if (weight == 0) return a;  // no walls (periodic box): exactly the +0 sums below, no divisions
  for (int d = 0; d < 3; ++d) {
    const Real below = std::min(Real(1), (lo[d] + margin - x[d]) / margin);
    const Real above = std::min(Real(1), (x[d] - (hi[d] - margin)) / margin);
    if (below > 0) a[d] += weight * below * below;
    if (above > 0) a[d] -= weight * above * above;
  }
  return a;
}

/// \brief Reynolds' prioritised acceleration allocation (spec 2.1): add the rule accelerations in
/// priority order (index 0 first) while the accumulated magnitude Σ|a_k| stays within `a_max`;
/// the first rule that does not fit is scaled to use up the rest and later rules are dropped.
/// So under pressure the high-priority rules (avoid collisions, flee) win outright instead of being
/// averaged away.
inline Vec3 prioritized_sum(std::span<const Vec3> rules, Real a_max) {
  Vec3 sum{};
  Real used = 0;
  for (const Vec3& a : rules) {
    const Real a2 = core::dot(a, a);
    if (a2 == 0) continue;  // norm 0 exactly when a2 is (sqrt(+0) = +0): no square root
    const Real m = std::sqrt(a2);
    if (used + m <= a_max) {
      sum += a;
      used += m;
    } else {
      sum += a * ((a_max - used) / m);
      break;
    }
  }
  return sum;
}

/// \brief Rotate `a` about the z axis by `angle` (rad): the 1/f heading fluctuation turns the
/// direction of the acceleration vector (spec 2.6, "the direction of the acceleration vector").
inline Vec3 rotate_z(const Vec3& a, Real angle) {
  // cos(±0) = 1 and sin(±0) = ±0 exactly: angle 0 (no heading noise) skips the libm call.
  Real c = 1, s = angle;
  if (angle != 0) c = std::cos(angle), s = std::sin(angle);
  // On FMA targets GCC compiles the plain form (c a.x - s a.y, ...) into one vfmaddsub (its
  // complex-multiply pattern fuses even with -ffp-contract=off), but only when the pattern
  // matches: the fused form is spelled out so the bits do not depend on that
  // (docs/performance-flock.md, boids3). On every build: without hardware FMA std::fma is a libm
  // call, one per prey and step, and the bits stay those of the FMA builds.
  return {std::fma(c, a.x, -(s * a.y)), std::fma(s, a.x, c * a.y), a.z};
}

/// \brief Semi-implicit Euler step (spec 2.1): v += a dt, clamp v_min <= |v| <= v_max, x += v dt.
/// The lower clamp keeps flying boids moving (a boid at rest has no heading); it is applied only
/// when |v| > 0.
inline void integrate(Vec3& x, Vec3& v, const Vec3& a, Real dt, Real v_min, Real v_max) {
  v += a * dt;
  const Real s2 = core::dot(v, v);
  if (s2 > v_max * v_max) {
    v *= v_max / std::sqrt(s2);
  } else if (s2 > 0 && s2 < v_min * v_min) {
    v *= v_min / std::sqrt(s2);
  }
  x += v * dt;
}

/// \brief Polarisation (order parameter) φ = |Σ v_i/|v_i|| / N over boids with |v| > 0, in [0, 1];
/// 0 if there are none. Summed in the given order (callers pass id order for reproducibility).
double polarisation(std::span<const Vec3> velocities);

}  // namespace biota::models::flock
